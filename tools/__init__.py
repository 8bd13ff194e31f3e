# SPDX-License-Identifier: MIT
"""The studies, the batch runner, the benchmark driver, the fuzzers and the table writers.
Run a tool as a module from the repository root: ``python3 -m tools.sweep --help``."""
