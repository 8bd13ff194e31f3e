#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every tool in tools/ and every script in plots/ answers --help (exit 0, a usage line on
# standard output, within 60 s) and writes nothing into the repository when asked for help: the tree (less
# build/, bin/, out/ and __pycache__/) holds no file newer than the start of this test, and
# `git status --porcelain` is unchanged (when this is a git work tree). Also: run_scenes.sh
# refuses an unknown scene (exit 2) without touching docs/figures/scenes.txt, and
# tools/stability.py defaults to the level `make stability` uses (quick); README.md, Makefile,
# namelists/, docs/, plots/, tools/, src/ and tests/*.f90 cite no internal document (METHOD.md,
# INTERFACE.md, ...).
#   usage: bash tests/test_tools.sh SCRATCH
set -u
if [ -n "${TUBEMPM_TEST_TOOLS:-}" ]; then   # a tool that ignored --help ran the test suite
  echo "test_tools: 0 passed, 1 failed (called from itself)"; exit 1
fi
export TUBEMPM_TEST_TOOLS=1
root=$(cd "$(dirname "$0")/.." && pwd)
scratch=${1:-/tmp/test_tools}
mkdir -p "$scratch"
py=${PYTHON:-python3}
pass=0; fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL [tools]: $*"; }
cd "$root"

# the files of the tree newer than the marker (outputs of builds and runs excluded)
changed() {
  find . \( -path ./build -o -path ./bin -o -path ./out -o -path ./.git -o -name __pycache__ \) \
    -prune -o -type f -newer "$scratch/marker" -print | sort
}
git_state() { git status --porcelain 2>/dev/null; }
touch "$scratch/marker"
sleep 1.1                                  # a file written now is strictly newer than the marker
status0=$(git_state)
scenes_sum0=$(cksum docs/figures/scenes.txt 2>/dev/null)

tools=$(ls tools/*.py tools/*.sh plots/plot_*.py plots/style.py | grep -v __init__)
for t in $tools; do
  case $t in
    *.py) m=${t%.py}; cmd=("$py" -m "${m//\//.}") ;;
    *.sh) cmd=(bash "$t") ;;
  esac
  out=$(timeout 60 "${cmd[@]}" --help 2> "$scratch/err" < /dev/null); rc=$?
  [ $rc -eq 0 ] && ok || bad "$t --help exits $rc, expected 0: $(head -c 300 "$scratch/err")"
  echo "$out" | grep -qi '^ *usage:' && ok || bad "$t --help prints no 'usage:' line"
  [ "$(echo "$out" | wc -l)" -ge 2 ] && ok || bad "$t --help prints a single line or nothing"
done
n=$(echo "$tools" | wc -w)
[ "$n" -ge 13 ] && ok || bad "expected at least 13 tools and scripts, found $n"

# run_scenes.sh: an unknown scene is refused before anything runs or is truncated
timeout 60 bash tools/run_scenes.sh nosuchscene > "$scratch/rs.out" 2>&1 < /dev/null; rc=$?
[ $rc -eq 2 ] && ok || bad "run_scenes.sh nosuchscene exits $rc, expected 2"
grep -q "unknown scene 'nosuchscene'" "$scratch/rs.out" && ok \
  || bad "run_scenes.sh nosuchscene does not name the unknown scene"
[ "$(cksum docs/figures/scenes.txt 2>/dev/null)" = "$scenes_sum0" ] && ok \
  || bad "docs/figures/scenes.txt changed"

# tools/stability.py and make stability default to the same level (quick)
level=$("$py" -c "from tools import stability; print(stability.parse_args([]).level)" \
        2> "$scratch/err")
[ "$level" = quick ] && ok || bad "tools/stability.py defaults to '$level', expected quick: $(head -c 300 "$scratch/err")"
make -n --no-print-directory stability 2>/dev/null | grep -qF -- "-m tools.stability --level quick" && ok \
  || bad "make stability does not run python3 -m tools.stability --level quick"
make -n --no-print-directory stability 2>/dev/null | grep -qF -- "-m plots.plot_stability --level quick" && ok \
  || bad "make stability does not draw the quick level's figures"

# the product cites its own docs and the literature, not the project's internal notes
cites=$(grep -rnE "(METHOD|INTERFACE|STYLE)\.md|shared/" README.md Makefile namelists docs plots tools \
        --include='*.md' --include='*.nml' --include='*.py' --include='*.sh' --include=Makefile 2>/dev/null;
       grep -rnE "(METHOD|INTERFACE|STYLE)\.md|shared/" src tests --include='*.f90' --include='*.c' \
        --include='*.inc' 2>/dev/null)
[ -z "$cites" ] && ok || bad "internal documents cited: $(echo "$cites" | head -3)"

# nothing written into the repository
new=$(changed)
[ -z "$new" ] && ok || bad "files written into the repository: $(echo $new)"
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  [ "$(git_state)" = "$status0" ] && ok || bad "git status --porcelain changed: $(git_state | head -5)"
fi
echo "test_tools: $pass passed, $fail failed"
[ $fail -eq 0 ]
