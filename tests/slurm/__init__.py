# SPDX-License-Identifier: MIT
"""The Slurm backend against a real one-node cluster (tests/slurm/run.sh)."""
