#!/usr/bin/env bash
# Fails (exit 1) when git tracks build output: Python caches, logs (e.g. a build.configure.log
# written next to the build directory), build*/ directories, object files and libraries, CMake's
# and Ninja's generated files. Prints the offending paths. Run by .ci/run first thing and by ctest
# (repo.clean_tree, label unit) in a git checkout.
# Usage: cmake/check-clean-tree.sh [repository root] (default: this script's repository).
set -euo pipefail
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}
if ! git -C "$root" rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  echo "check-clean-tree: $root is not a git checkout" >&2
  exit 2
fi
# One extended regular expression per kind of build output, matched against the tracked paths.
patterns=(
  '(^|/)__pycache__/' '\.py[cod]$'                                   # Python
  '\.log$'                                                           # logs
  '^build[^/]*/' '(^|/)CMakeFiles/' '(^|/)CMakeCache\.txt$'          # CMake build trees
  '(^|/)cmake_install\.cmake$' '(^|/)CTestTestfile\.cmake$' '(^|/)Testing/Temporary/'
  '(^|/)compile_commands\.json$' '(^|/)build\.ninja$' '(^|/)\.ninja_'
  '\.(o|obj|a|lib|so|so\.[0-9.]+|dylib|dll|exe|gch|pch)$'           # objects, libraries
)
regex=$(IFS='|'; echo "${patterns[*]}")
found=$(git -C "$root" ls-files | grep -E "$regex" || true)
if [ -n "$found" ]; then
  echo "check-clean-tree: git tracks build output (git rm --cached it; .gitignore lists it):" >&2
  echo "$found" | sed 's/^/  /' >&2
  exit 1
fi
echo "check-clean-tree: no build output tracked"
