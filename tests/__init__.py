# SPDX-License-Identifier: MIT
"""The tests; a Python test runs as a module from the repository root:
``python3 -m tests.test_outputs SCRATCH`` (tools/run-tests.sh runs them all)."""
