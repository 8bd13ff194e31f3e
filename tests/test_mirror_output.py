#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The mirror images of half and quarter models in particles.h5 and particles.xdmf
(docs/output.md, "Mirror images"; `&run mirror_images`).

Runs small half and quarter rings (CPDI2, whose corners are shared, and uGIMP, four corners per
particle) with the binary named by TUBEMPM and checks every snapshot against the reflections
themselves, not against the code's own routine: in the subgroup `mirrored`, copy k of the
sector (rows k np + 1 .. (k + 1) np; `image` = k) is reflected across x = x_c for k = 1 and,
for a quarter, across y = y_c for k = 2 and both for k = 3, where x_c, y_c are the ring centre
of the input. Exactly (bit for bit): a reflected coordinate is 2 c - x, the velocity component
normal to the plane changes sign, sxy and F12, F21 change sign once per reflection, every other
value is the sector's; the corners are reflected and each image particle's corners are the
sector's, in reverse order after one reflection (not after two: a half turn), so that every
domain stays counter-clockwise (signed area > 0, and
equal to the sector's). The XDMF index points at the whole tube. With mirror_images = .false.
there is no subgroup, the index points at the sector, and history.csv and the sector's datasets
are identical to the run with images (the option changes the output only). Before the images
there was no subgroup: every check of it failed. Prints `test_mirror_output: N passed, M failed`.
"""
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from tests.pycheck import Checks

ROOT = Path(__file__).resolve().parent.parent
BIN = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
T = Checks("test_mirror_output")
check = T.check

CENTER = (0.0013, 0.0262)          # not on a node line of the lattice's origin: c is read back

HALF = """&run title = '{name}', output_dir = '{out}', t_end = 4.0e-5, snapshot_every = 2.0e-5 {extra}/
&solver basis = '{basis}' /
&grid h = 1.0e-3 /
&material name = 'alu', model = 'j2', E = 70.0e9, nu = 0.33, rho = 2700.0, sigma_y = 150.0e6 /
&body center = {cx}, {cy}, r_inner = 0.024, r_outer = 0.026, n_thick = 4,
  velocity = 0.0, -30.0, sector = 'half' /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
"""
QUARTER = """&run title = '{name}', output_dir = '{out}', t_end = 4.0e-5, snapshot_every = 2.0e-5 {extra}/
&solver basis = '{basis}' /
&grid h = 1.0e-3 /
&material name = 'alu', model = 'j2', E = 70.0e9, nu = 0.33, rho = 2700.0, sigma_y = 150.0e6 /
&body center = {cx}, {cy}, r_inner = 0.024, r_outer = 0.026, n_thick = 4, sector = 'quarter' /
&wall point = 0.0, 0.0522, normal = 0.0, -1.0, velocity = 0.0, -30.0 /
"""


def run(scratch: Path, name: str, template: str, basis: str = "cpdi2", extra: str = "") -> Path:
    out = scratch / name
    nml = scratch / f"{name}.nml"
    nml.write_text(template.format(name=name, out=out, basis=basis, extra=extra,
                                   cx=CENTER[0], cy=CENTER[1]))
    p = subprocess.run([BIN, "--quiet", str(nml)], capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"), timeout=600)
    check(p.returncode == 0, f"{name}: the run exits 0 (exit {p.returncode}: {p.stderr[-300:]})")
    return out


def signed_areas(corners: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Shoelace areas of the quadrilaterals (positive when counter-clockwise)."""
    v = corners[quads]                      # (n, 4, 2)
    x, y = v[:, :, 0], v[:, :, 1]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)


def check_images(out: Path, what: str, n_images: int) -> None:
    import h5py
    flips = {1: (True, False), 2: (False, True), 3: (True, True)} if n_images == 4 \
        else {1: (True, False)}
    xdmf = (out / "particles.xdmf").read_text()
    with h5py.File(out / "particles.h5", "r") as f:
        snaps = sorted(k for k in f if k.startswith("snap_"))
        check(len(snaps) == 3, f"{what}: 3 snapshots ({len(snaps)})")
        for name in snaps:
            g = f[name]
            if not check("mirrored" in g, f"{what}/{name}: a subgroup 'mirrored'"):
                continue
            m = g["mirrored"]
            n = g["x"].shape[0]
            nc = g["corners"].shape[0]
            check(int(m.attrs["images"]) == n_images and int(m.attrs["np"]) == n_images * n
                  and int(m.attrs["ncorner"]) == n_images * nc,
                  f"{what}/{name}: images {m.attrs['images']}, np {m.attrs['np']}, "
                  f"ncorner {m.attrs['ncorner']} for {n} particles, {nc} corners")
            c = [float(m.attrs["mirror_x"]), float(m.attrs["mirror_y"]) if n_images == 4
                 else None]
            check(c[0] == CENTER[0] and (n_images == 2 or c[1] == CENTER[1]),
                  f"{what}/{name}: the planes are the ring centre's lines ({c})")
            check(n_images == 4 or "mirror_y" not in m.attrs, f"{what}/{name}: no y plane")
            check(np.array_equal(m["image"][()], np.repeat(np.arange(n_images), n)),
                  f"{what}/{name}: image = the copy number, block by block")
            x, v, s, F = (g[k][()] for k in ("x", "v", "stress", "F"))
            corners, quads = g["corners"][()], g["quads"][()]
            area0 = signed_areas(corners, quads)
            check(np.all(area0 > 0), f"{what}/{name}: the sector's domains are counter-clockwise")
            for k in range(n_images):
                rows = slice(k * n, (k + 1) * n)
                fx = flips.get(k, (False, False))
                sign = (-1.0) ** sum(fx)
                xe, ve, ce = x.copy(), v.copy(), corners.copy()
                for d in range(2):
                    if fx[d]:
                        xe[:, d] = 2.0 * c[d] - x[:, d]
                        ce[:, d] = 2.0 * c[d] - corners[:, d]
                        ve[:, d] = -v[:, d]
                se = s.copy()
                se[:, 2] = sign * s[:, 2]           # sxy
                Fe = F.copy()
                Fe[:, 1:3] = sign * F[:, 1:3]       # F21, F12
                tag = f"{what}/{name} copy {k} (flips x {fx[0]}, y {fx[1]})"
                check(np.array_equal(m["x"][rows], xe), f"{tag}: positions reflected exactly")
                check(np.array_equal(m["v"][rows], ve), f"{tag}: normal velocity negated")
                check(np.array_equal(m["stress"][rows], se), f"{tag}: sxy x {sign:+g}, rest same")
                check(np.array_equal(m["F"][rows], Fe), f"{tag}: F12, F21 x {sign:+g}")
                check(np.array_equal(m["vx"][rows], ve[:, 0]) and
                      np.array_equal(m["vy"][rows], ve[:, 1]) and
                      all(np.array_equal(m[a][rows], se[:, j])
                          for j, a in enumerate(("sxx", "syy", "sxy", "szz"))),
                      f"{tag}: the 1-D columns vx, vy, sxx, syy, sxy, szz")
                check(all(np.array_equal(m[a][rows], g[a][()])
                          for a in ("mass", "volume", "eqps", "body")),
                      f"{tag}: mass, volume, eqps, body unchanged")
                qk = m["quads"][rows]
                cm = m["corners"][()]
                check(np.array_equal(cm[k * nc:(k + 1) * nc], ce), f"{tag}: corners reflected")
                order = [0, 3, 2, 1] if sum(fx) == 1 else [0, 1, 2, 3]
                check(np.array_equal(cm[qk], ce[quads][:, order]),
                      f"{tag}: each domain's corners are the sector's (reversed in an image)")
                area = signed_areas(cm, qk)
                check(np.all(area > 0) and np.allclose(area, area0, rtol=1e-12, atol=0),
                      f"{tag}: counter-clockwise, areas of the sector (min {area.min():.3g})")
            mass = m["mass"][()]
            com = (mass[:, None] * m["x"][()]).sum(axis=0) / mass.sum()
            for d in range(2 if n_images == 4 else 1):
                check(abs(com[d] - c[d]) <= 1e-12, f"{what}/{name}: the whole tube's centre of "
                      f"mass lies on the plane ({com[d]} vs {c[d]})")
            ref = f"particles.h5:/{name}/mirrored/quads"
            check(ref in xdmf and f'NumberOfElements="{n_images * n}"' in xdmf,
                  f"{what}/{name}: the XDMF index points at the whole tube")


def main() -> int:
    scratch = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    scratch.mkdir(parents=True, exist_ok=True)
    import h5py
    for basis in ("cpdi2", "ugimp"):
        check_images(run(scratch, f"half_{basis}", HALF, basis), f"half {basis}", 2)
        check_images(run(scratch, f"quarter_{basis}", QUARTER, basis), f"quarter {basis}", 4)
    on = scratch / "quarter_cpdi2"
    off = run(scratch, "quarter_off", QUARTER, extra=", mirror_images = .false. ")
    nml_on, nml_off = (d / "input.nml" for d in (on, off))
    check("mirror_images" not in nml_on.read_text(),
          "input.nml leaves out mirror_images at its default (.true.)")
    check(re.search(r"(?m)^\s*mirror_images = \.false\.", nml_off.read_text()) is not None,
          "input.nml writes mirror_images = .false. when it is off")
    hist_on = (on / "history.csv").read_text()
    hist_off = (off / "history.csv").read_text()
    check(hist_on == hist_off, "history.csv is the same with and without the images")
    with h5py.File(on / "particles.h5", "r") as fa, h5py.File(off / "particles.h5", "r") as fb:
        for name in sorted(k for k in fb if k.startswith("snap_")):
            check("mirrored" not in fb[name], f"off/{name}: no subgroup 'mirrored'")
            check(all(np.array_equal(fa[name][d][()], fb[name][d][()]) for d in fb[name]),
                  f"off/{name}: the sector's datasets equal those of the run with images")
    check("mirrored" not in (off / "particles.xdmf").read_text(),
          "off: the XDMF index points at the sector")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
