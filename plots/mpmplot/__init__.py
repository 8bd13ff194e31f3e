# SPDX-License-Identifier: MIT
"""Reading tubempm outputs and comparing them with closed forms, without matplotlib.

One module per concern (import the one you need: ``from plots.mpmplot import readers``, with
the repository root as the current folder, as ``python3 -m plots.plot_case`` has it):

* :mod:`mpmplot.namelist`  the only namelist reader and editor (input.nml, summary.nml, case
  files)
* :mod:`mpmplot.readers`   history.csv, summary.nml, particles.h5, measured curves
* :mod:`mpmplot.scene`     what a case is: output folder, walls, ring, kind of scene
* :mod:`mpmplot.theory`    closed forms of docs/method.md (DeRuntz-Hodge, ring stiffness, waves)
* :mod:`mpmplot.analysis`  post-processing of history columns (contact, rebound, arrivals)

It needs numpy, and h5py only for the particle files (imported when first needed). It never
imports matplotlib, so tests can use it without a display or a plotting stack. SI units.
"""
