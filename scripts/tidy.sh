#!/usr/bin/env bash
# clang-tidy with the project's .clang-tidy on the given sources (default: the library and app
# sources changed against HEAD~1), using build/compile_commands.json.
#   bash scripts/tidy.sh                      # changed files
#   bash scripts/tidy.sh src/gridshell/pipeline/*.cpp
#   bash scripts/tidy.sh --all                # every library and app source (~30 s a file)
# The build's GCC-only warning flags (-Wshadow=local) are unknown to clang: they are ignored
# rather than reported as an error for every file.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f build/compile_commands.json ] ||
  cmake -S . -B build -G Ninja >/dev/null
files=("$@")
if [ "${1:-}" = "--all" ]; then
  mapfile -t files < <(git ls-files 'src/*.cpp' 'app/*.cpp')
elif [ ${#files[@]} -eq 0 ]; then
  mapfile -t files < <(git diff --name-only HEAD~1 -- 'src/*.cpp' 'app/*.cpp')
fi
[ ${#files[@]} -eq 0 ] && { echo "tidy: no sources to check"; exit 0; }
clang-tidy -p build --quiet --extra-arg=-Wno-unknown-warning-option "${files[@]}"
