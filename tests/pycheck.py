# SPDX-License-Identifier: MIT
"""Check counting for the Python tests, the counterpart of tests/testing.f90.

    from tests.pycheck import Checks, close
    t = Checks("test_name")
    t.check(x > 0, "x is positive")          # counts; prints a FAIL line when false
    sys.exit(t.summary())                    # prints `test_name: N passed, M failed`, 1 if M > 0

tools/run-tests.sh sums the summary lines. Not a test itself (no test_ prefix).
"""
from __future__ import annotations

import math


class Checks:
    """Counts passed and failed checks of one test script."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.passed = 0
        self.failed = 0

    def check(self, cond: bool, msg: str) -> bool:
        """Count one check; print a line for a failure. Returns the condition."""
        if cond:
            self.passed += 1
        else:
            self.failed += 1
            print(f"FAIL [{self.name}]: {msg}")
        return bool(cond)

    def summary(self) -> int:
        """Print the summary line (last) and return the exit status: 1 if anything failed."""
        print(f"{self.name}: {self.passed} passed, {self.failed} failed")
        return 1 if self.failed else 0


def close(a: float, b: float, rtol: float = 1e-12, atol: float = 0.0) -> bool:
    """|a - b| <= max(atol, rtol |b|), False for NaN."""
    return math.isfinite(a) and math.isfinite(b) and abs(a - b) <= max(atol, rtol * abs(b))
