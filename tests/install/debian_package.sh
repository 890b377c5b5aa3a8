#!/usr/bin/env bash
# `cpack -G DEB` on the build tree: the package's control fields and contents, and the
# program unpacked from it (dpkg -x, away from the build tree) running.
#   tests/install/debian_package.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"
fail() { echo "FAIL: $*" >&2; exit 1; }

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# -B keeps CPack's staging folder out of the build tree as well.
(cd "$tmp" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/pkg" >cpack.log 2>&1) ||
  { cat "$tmp/cpack.log" >&2; fail "cpack -G DEB failed"; }
debs=("$tmp"/pkg/*.deb)
[ "${#debs[@]}" -eq 1 ] && [ -s "${debs[0]}" ] || fail "expected one .deb, found: ${debs[*]}"
deb="${debs[0]}"
echo "package: $(basename "$deb")"

info="$(dpkg-deb -I "$deb")"
depends="$(dpkg-deb -f "$deb" Depends)"
echo "Depends: $depends"
grep -q 'gnuplot-nox' <<<"$depends" || fail "Depends does not name gnuplot-nox"
grep -q 'libboost-iostreams' <<<"$depends" || fail "Depends lacks the shared libraries (dpkg-shlibdeps)"
grep -q 'libc6' <<<"$depends" || fail "Depends lacks libc6 (dpkg-shlibdeps)"
for field in Maintainer Section Description; do
  grep -q "^ $field: ." <<<"$info" || fail "the control file has no $field"
done

contents="$(dpkg-deb -c "$deb")"
for f in ./usr/bin/millwear ./usr/share/man/man1/millwear.1.gz \
         ./usr/share/bash-completion/completions/millwear ./usr/share/millwear/plots/fig7_area.gp \
         ./usr/share/millwear/scenarios/lab-mill.toml ./usr/share/millwear/profiles/lab-2x30.toml; do
  grep -q " $f\$" <<<"$contents" || fail "the package does not contain $f"
done
if grep -E 'millwear_tests|bench_|stability_sweep|/tests/' <<<"$contents"; then
  fail "the package contains tests or benchmarks"
fi

# Every dependency resolves on this system (what apt would install with the package).
apt-get install --simulate -qq "$deb" >"$tmp/apt.log" 2>&1 ||
  { cat "$tmp/apt.log" >&2; fail "apt-get cannot resolve the package's dependencies"; }

dpkg -x "$deb" "$tmp/root"
unset MILLWEAR_PLOTS_DIR
cd "$tmp"
version="$("$tmp/root/usr/bin/millwear" --version)"
echo "$version"
[[ "$version" =~ ^millwear\ [0-9.]+\ \(commit\ ([0-9a-f]{7}(-dirty)?|unknown)\)$ ]] ||
  fail "--version of the packaged program: $version"
out="$("$tmp/root/usr/bin/millwear" profile "$tmp/root/usr/share/millwear/profiles/lab-2x30.toml")" ||
  fail "millwear profile failed on the packaged profile"
echo "$out"
grep -q 'lab-2x30' <<<"$out" || fail "millwear profile does not list lab-2x30"
echo "package OK"
