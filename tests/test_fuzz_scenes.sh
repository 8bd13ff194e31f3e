#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# 14 valid but extreme scenes run to their end (tools/fuzz_scenes.py: bodies at the edge of a
# fixed grid, fast bodies leaving a fitted grid, platens driven through a ring, one particle
# through the wall, many particles under a memory limit, random solver settings): every run
# must exit 0, or 2 or 4 with an ERROR line, with no runtime or sanitizer report, within
# 120 s. `make fuzz-scenes N=...` runs more.
set -u
scratch=${1:-$(mktemp -d)}
out=$(${PYTHON:-python3} -m tools.fuzz_scenes --bin "${TUBEMPM:-bin/tubempm}" --count 14 \
      --seed 2026 --out "$scratch/fuzz_scenes" 2>&1)
rc=$?
echo "$out" | grep -v "passed, .* failed$"
line=$(echo "$out" | grep -E "^fuzz_scenes: [0-9]+ passed, [0-9]+ failed$" | sed 's/^fuzz_scenes:/test_fuzz_scenes:/')
[ -n "$line" ] && echo "$line" || echo "test_fuzz_scenes: 0 passed, 1 failed"
exit $rc
