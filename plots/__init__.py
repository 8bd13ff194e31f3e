# SPDX-License-Identifier: MIT
"""Plotting and post-processing of tubempm runs (plots/README.md). Run a script as a module
from the repository root: ``python3 -m plots.plot_case --case namelists/crush.nml``."""
