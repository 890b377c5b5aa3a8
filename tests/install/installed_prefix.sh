#!/usr/bin/env bash
# `cmake --install` into a prefix that is then moved, so neither the build tree nor the
# original prefix can be reached; the moved program runs a small wear history from another
# folder and must find its figure scripts on its own.
#   tests/install/installed_prefix.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1" source="$2"
fail() { echo "FAIL: $*" >&2; exit 1; }

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cp -a "$tmp/prefix" "$tmp/moved"
rm -rf "$tmp/prefix"
p="$tmp/moved"
unset MILLWEAR_PLOTS_DIR
export PATH="$p/bin:$PATH"

for f in bin/millwear share/man/man1/millwear.1.gz share/bash-completion/completions/millwear \
         share/millwear/plots/fig7_area.gp share/millwear/plots/common.gp \
         share/millwear/scenarios/lab-mill.toml share/millwear/profiles/lab-2x30.toml \
         share/millwear/validation/hardness-synthetic.csv share/millwear/validation/lab-mill-guess.toml \
         share/doc/millwear/README.md share/doc/millwear/docs/run.md; do
  [ -s "$p/$f" ] || fail "$f is missing or empty in the installed tree"
done
# Every relative link of an installed Markdown file resolves in the moved tree.
while IFS= read -r md; do
  # The target of each ](...) up to an anchor, a space (a title) or the closing parenthesis;
  # web addresses are not files.
  for target in $(grep -oE '\]\([^)#[:space:]]+' "$md" | sed 's/^](//'); do
    case "$target" in *://*|mailto:*) continue ;; esac
    [ -e "$(dirname "$md")/$target" ] || fail "${md#"$p"/} links $target, which is not installed"
  done
done < <(find -L "$p/share" -name '*.md')

# --version names the commit: seven hex digits (and -dirty) in a git checkout, else unknown.
version="$(millwear --version)"
echo "$version"
if git -C "$source" rev-parse HEAD >/dev/null 2>&1; then
  [[ "$version" =~ ^millwear\ [0-9]+\.[0-9]+\.[0-9]+\ \(commit\ [0-9a-f]{7}(-dirty)?\)$ ]] ||
    fail "--version does not name a commit: $version"
else
  [[ "$version" =~ ^millwear\ [0-9.]+\ \(commit\ unknown\)$ ]] || fail "--version: $version"
fi

# The man page is help2man's rendering of --help: a title and the commands.
man="$(gzip -dc "$p/share/man/man1/millwear.1.gz")"
grep -Eq '^\.TH MILLWEAR "?1"? ' <<<"$man" || fail "the man page has no .TH MILLWEAR 1 title line"
grep -q 'MILLWEAR_PLOTS_DIR' <<<"$man" || fail "the man page does not describe MILLWEAR_PLOTS_DIR"
for c in run profile screen; do
  grep -q "$c" <<<"$man" || fail "the man page does not mention '$c'"
done

# The completion script completes subcommands, options and file names.
bash -n "$p/share/bash-completion/completions/millwear" || fail "completion script: syntax"
mkdir -p "$tmp/here/scenes"
complete_words() {  # the words offered for the command line "$@" (last word being completed)
  bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1))
           COMP_LINE="$*"; COMP_POINT=${#COMP_LINE}; _millwear millwear
           printf "%s\n" "${COMPREPLY[@]}"' _ "$p/share/bash-completion/completions/millwear" "$@"
}
# The words are captured before grep reads them: `grep -q` stops at the first match, and under
# pipefail the writer's SIGPIPE would fail the pipeline whenever it loses that race.
offers() {  # offers PATTERN WORDS...: the completion of WORDS offers a word matching PATTERN
  local pattern="$1" words
  shift
  words="$(cd "$tmp/here" && complete_words "$@")"
  grep -qxE -- "$pattern" <<<"$words"
}
offers run millwear r || fail "completion: 'r' does not offer run"
offers --fidelity millwear run --fi ||
  fail "completion: 'run --fi' does not offer --fidelity"
offers draft millwear run --fidelity d ||
  fail "completion: 'run --fidelity d' does not offer draft"
offers 'scenes/?' millwear run sc ||
  fail "completion: 'run sc' does not offer the folder scenes/"

# Every installed scene resolves its ../profiles/ from where it was installed; the screen
# file its base scene and equal-area profile (--emit writes the job list, runs nothing).
for s in lab-mill lab-hi-lo lab-worn-start sag-1x30 sag-2x30 sag-2x30-vs-1x30 sag-hi-lo; do
  (cd "$tmp/here" && millwear run "$p/share/millwear/scenarios/$s.toml" -o out-check --check \
     >/dev/null) || fail "the installed scene $s.toml does not validate"
done
(cd "$tmp/here" && millwear screen "$p/share/millwear/scenarios/screen-sag-face-angle.toml" \
   -o out-screen --emit parallel >/dev/null) || fail "the installed screen file does not validate"
# The README's validation examples, from the installed copies.
(cd "$tmp/here" && millwear run "$p/share/millwear/validation/lab-mill-guess.toml" -o out-guess --check \
   >/dev/null) || fail "the installed validation/lab-mill-guess.toml does not validate"
(cd "$tmp/here" && millwear hardness "$p/share/millwear/validation/hardness-synthetic.csv" -o out-hard \
   >/dev/null) || fail "millwear hardness on the installed validation/hardness-synthetic.csv failed"

# The quick lab scene (tests/data/lab-quick.toml names ../../profiles/lab-2x30.toml), with the
# installed profile, run from a third folder.
cp "$source/tests/data/lab-quick.toml" "$tmp/here/scenes/"
mkdir -p "$tmp/profiles" "$tmp/elsewhere"
cp "$p/share/millwear/profiles/lab-2x30.toml" "$tmp/profiles/"
cd "$tmp/elsewhere"
millwear run ../here/scenes/lab-quick.toml -o out --fidelity draft --quiet ||
  fail "the installed millwear run failed"
for fig in fig6_profiles fig7_area fig8_power fig9_collision fig10_utilization spectrum \
           snapshot_lab-quick; do
  [ -s "out/plots/$fig.png" ] || fail "out/plots/$fig.png is missing or empty"
done
echo "installed tree OK: $(ls out/plots/*.png | wc -l) PNG figures"
