#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# 200 namelist mutations through `tubempm --check` (tools/fuzz_namelists.py): every mutant must
# exit 0, or exit 2 with an ERROR line, within 10 s. `make fuzz` runs thousands.
set -u
scratch=${1:-$(mktemp -d)}
out=$(${PYTHON:-python3} -m tools.fuzz_namelists --bin "${TUBEMPM:-bin/tubempm}" --count 200 \
      --seed 2026 --out "$scratch/fuzz" 2>&1)
rc=$?
echo "$out" | grep -v "passed, .* failed$"
line=$(echo "$out" | grep -E "^fuzz: [0-9]+ passed, [0-9]+ failed$" | sed 's/^fuzz:/test_fuzz:/')
[ -n "$line" ] && echo "$line" || echo "test_fuzz: 0 passed, 1 failed"
exit $rc
