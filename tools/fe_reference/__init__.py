# SPDX-License-Identifier: MIT
"""The finite element references (docs/fe_reference/README.md):
``python3 -m tools.fe_reference.fe_reference`` from the repository root."""
