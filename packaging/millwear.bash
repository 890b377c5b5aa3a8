# bash completion for millwear: subcommands, their options, the values of options that list
# them in their help ("draft | standard | reference"), and file names for the rest.
#
# The subcommands and options are read from the program's own --help (once per shell for
# each subcommand), so the completion follows the program it completes, whichever it is:
# `millwear`, or `./build/millwear` in a build tree.

declare -gA _millwear_help_cache

# The --help text of "$1 $2" (no $2: the program's own), cached.
_millwear_help() {
  local key="$1|$2"
  if [[ -z "${_millwear_help_cache[$key]+set}" ]]; then
    if [[ -n "$2" ]]; then
      _millwear_help_cache[$key]="$("$1" "$2" --help 2>/dev/null)"
    else
      _millwear_help_cache[$key]="$("$1" --help 2>/dev/null)"
    fi
  fi
  printf '%s\n' "${_millwear_help_cache[$key]}"
}

# The subcommand names: the first word of each line of the "Subcommands:" section.
_millwear_subcommands() {
  local line section=""
  while IFS= read -r line; do
    if [[ "$line" =~ ^[A-Za-z] ]]; then
      section="$line"
    elif [[ "$section" == Subcommands:* && "$line" =~ ^\ +([a-z0-9][a-z0-9_-]*) ]]; then
      printf '%s\n' "${BASH_REMATCH[1]}"
    fi
  done < <(_millwear_help "$1" "")
}

# One line per option of the "Options:" section of "$1 $2 --help":
#   NAME TYPE VALUES   (TYPE "-" for a flag, else CLI11's type word: TEXT, INT, TEXT:FILE, ...;
#                       VALUES the choices listed as "a | b | c" at the start of its help)
_millwear_options() {
  local line section="" names type rest values name
  while IFS= read -r line; do
    if [[ "$line" =~ ^[A-Za-z] ]]; then
      section="$line"
      continue
    fi
    [[ "$section" == Options:* && "$line" =~ ^\ +(-[^ ]+)\ *(.*)$ ]] || continue
    names="${BASH_REMATCH[1]}" rest="${BASH_REMATCH[2]}" type="-" values=""
    if [[ "$rest" =~ ^[A-Z][A-Z0-9_]*:\{([^}]*)\} ]]; then  # a set check: TEXT:{a,b,c}
      type="TEXT" values="${BASH_REMATCH[1]}"
    elif [[ "$rest" =~ ^([A-Z][A-Z0-9_:]*)( |$) ]]; then
      type="${BASH_REMATCH[1]}"
      rest="${rest#"$type"}"
      rest="${rest#"${rest%%[![:space:]A-Z.]*}"}"  # past REQUIRED, "...", the padding
      if [[ "$rest" =~ ^([a-z0-9_-]+( \| [a-z0-9_-]+)+) ]]; then
        values="${BASH_REMATCH[1]// | /,}"
      fi
    fi
    for name in ${names//,/ }; do
      printf '%s %s %s\n' "$name" "$type" "${values:--}"
    done
  done < <(_millwear_help "$1" "$2")
}

_millwear_files() {
  compopt -o filenames 2>/dev/null
  if declare -F _filedir >/dev/null; then
    _filedir
  else
    local IFS=$'\n'
    COMPREPLY=($(compgen -f -- "$cur"))
  fi
}

_millwear() {
  local cur="${COMP_WORDS[COMP_CWORD]}" prev="" prog="${COMP_WORDS[0]}"
  ((COMP_CWORD > 0)) && prev="${COMP_WORDS[COMP_CWORD - 1]}"
  prog="${prog/#\~/$HOME}"
  command -v "$prog" >/dev/null 2>&1 || prog=millwear
  COMPREPLY=()

  # The subcommand: the first word after the program that is not an option.
  local i sub=""
  for ((i = 1; i < COMP_CWORD; i++)); do
    if [[ "${COMP_WORDS[i]}" != -* ]]; then
      sub="${COMP_WORDS[i]}"
      break
    fi
  done
  if [[ -z "$sub" ]]; then
    if [[ "$cur" == -* ]]; then
      COMPREPLY=($(compgen -W "-h --help --version" -- "$cur"))
    else
      COMPREPLY=($(compgen -W "$(_millwear_subcommands "$prog")" -- "$cur"))
    fi
    return 0
  fi

  local name type values
  if [[ "$prev" == -* ]]; then
    while read -r name type values; do
      [[ "$name" == "$prev" ]] || continue
      case "$type" in
        -) break ;;  # a flag: what follows is not its value
        INT | UINT | FLOAT | NUMBER | INT:* | UINT:* | FLOAT:* | NUMBER:*) return 0 ;;
      esac
      if [[ "$values" != - ]]; then
        COMPREPLY=($(compgen -W "${values//,/ }" -- "$cur"))
      else
        _millwear_files
      fi
      return 0
    done < <(_millwear_options "$prog" "$sub")
  fi

  if [[ "$cur" == -* ]]; then
    COMPREPLY=($(compgen -W "$(_millwear_options "$prog" "$sub" | cut -d' ' -f1)" -- "$cur"))
  else
    _millwear_files  # the positionals are scene, profile, screen and data files or folders
  fi
  return 0
}

complete -F _millwear millwear
