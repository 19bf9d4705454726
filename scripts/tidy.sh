#!/usr/bin/env bash
# clang-tidy with the project's .clang-tidy on the given sources (default: the library and app
# sources changed against origin's main or HEAD~1), using build/compile_commands.json.
#   bash scripts/tidy.sh                      # changed files
#   bash scripts/tidy.sh src/gridshell/pipeline/*.cpp
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f build/compile_commands.json ] || cmake -S . -B build -G Ninja >/dev/null
files=("$@")
if [ ${#files[@]} -eq 0 ]; then
  mapfile -t files < <(git diff --name-only HEAD~1 -- 'src/*.cpp' 'app/*.cpp')
fi
[ ${#files[@]} -eq 0 ] && { echo "tidy: no sources to check"; exit 0; }
clang-tidy -p build --quiet "${files[@]}"
