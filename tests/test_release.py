# SPDX-License-Identifier: MIT
"""`&run end_at_release` (src/driver/mpm_release.f90): a run ends when its contact is over.

Scenes (debug build, one thread, about 20 s in all):

1. an aluminium ring (J2) hitting a rigid target at 30 m/s, half model (its mirror plane is a
   'slip' wall whose reaction lasts the whole run and must not count as contact), run once to
   t_end and once with end_at_release:
   - the early run ends before t_end, with status 'completed' and the message naming the
     contact's times; the contact's last force is 0.1 x the contact time or more before the end;
   - up to its end the early run is the full run (every history row identical): the option
     only ends the run;
   - after the release no external force acts across the target's normal, so the full run's
     rebound velocity at t_end equals the early run's at its end (momentum conservation, to
     1e-9 relative): ending at the release loses nothing of the rebound;
   - the early run took fewer steps.
2. two rings colliding head-on (contact between bodies, no wall but the mirror plane): the run
   ends after the rings part, and the total momentum is conserved to 1e-12 x m V.
3. a crush (a platen moving for the whole run) never releases: it runs to t_end.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

from tests.pycheck import Checks
from tests.pyscene import run_scene

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_release")
check = T.check

AL = ("&material name = 'al', model = 'j2', E = 70.0e9, nu = 0.33, rho = 2700.0, "
      "sigma_y = 150.0e6, hardening = 200.0e6 /\n")
RING = ("&body center = 0.0, {y}, r_inner = 10.0e-3, r_outer = 12.0e-3, n_thick = 4, "
        "velocity = 0.0, {v}, sector = 'half' /\n")


def run(scratch: Path, name: str, text: str) -> tuple[dict, dict]:
    """Run one scene; its history and summary ({} when it failed): pyscene.run_scene."""
    return run_scene(T, scratch, name, text)


def contact_times(summary: dict) -> tuple[float, float] | None:
    """The contact's first and last times from the summary's message."""
    m = re.search(r"contact from t = (\S+) to (\S+) s", str(summary.get("message", "")))
    return (float(m.group(1)), float(m.group(2))) if m else None


def ring_on_target(scratch: Path) -> None:
    head = ("&run t_end = 1.2e-3, history_every = 5.0e-6, output_dir = 'OUT'{extra} /\n"
            "&grid h = 1.0e-3 /\n" + AL + RING.format(y=0.0125, v=-30.0)
            + "&wall point = 0.0, 0.0, normal = 0.0, 1.0 /\n")
    full, sf = run(scratch, "target_full", head.format(extra=""))
    early, se = run(scratch, "target_release", head.format(extra=", end_at_release = .true."))
    if not full or not early:
        return
    t_end = 1.2e-3
    check(early["time"][-1] < 0.9 * t_end, f"ends before t_end: {early['time'][-1]:.4e} s "
                                           f"(t_end {t_end:g} s)")
    check(sf["status"] == "completed" and se["status"] == "completed",
          f"status completed: {sf['status']}, {se['status']}")
    ct = contact_times(se)
    if check(ct is not None, f"message names the contact: {se.get('message')!r}"):
        t1, t2 = ct
        hold = early["time"][-1] - t2
        check(hold >= 0.1 * (t2 - t1) * (1 - 1e-9), f"contact-free for {hold:.3e} s >= 0.1 x "
                                                    f"{t2 - t1:.3e} s before the end")
        on = full["time"][full["wall1_force"] > 0.0]
        check(abs(on[-1] - t2) <= 5.0e-6 + 1e-12, f"the last contact force of the full run "
                                                  f"({on[-1]:.4e} s, rows every 5 us) is the "
                                                  f"message's ({t2:.4e} s)")
    n = len(early["time"])
    same = all(np.array_equal(early[k][:n - 1], full[k][:n - 1]) for k in early)
    check(same, "every history row before the last is the full run's")
    vy_e, vy_f = early["com_vy"][-1], full["com_vy"][-1]
    check(vy_e > 0.0 and abs(vy_e - vy_f) <= 1e-9 * abs(vy_f),
          f"rebound velocity at the release {vy_e:.12g} m/s = at t_end {vy_f:.12g} m/s "
          f"(1e-9; no force across the target's normal after the release)")
    check(early["step"][-1] < 0.9 * full["step"][-1],
          f"fewer steps: {int(early['step'][-1])} against {int(full['step'][-1])}")
    print(f"  ring on target: ends at {early['time'][-1]:.4e} s (t_end {t_end:g}), "
          f"{int(early['step'][-1])} of {int(full['step'][-1])} steps, rebound {vy_e:.6f} m/s")


def two_rings(scratch: Path) -> None:
    text = ("&run t_end = 1.0e-3, history_every = 5.0e-6, output_dir = 'OUT', "
            "end_at_release = .true. /\n&grid h = 1.0e-3 /\n" + AL
            + RING.format(y=0.0125, v=-30.0) + RING.format(y=-0.0125, v=30.0))
    h, s = run(scratch, "two_rings", text)
    if not h:
        return
    check(h["time"][-1] < 0.9e-3, f"two rings: ends at {h['time'][-1]:.4e} s, before t_end")
    check(h["contact1_2_force"][-1] == 0.0 and h["body1_vy"][-1] > 0.0 > h["body2_vy"][-1],
          f"two rings part: no contact force, body 1 (upper) {h['body1_vy'][-1]:.4f} m/s up, "
          f"body 2 {h['body2_vy'][-1]:.4f} m/s down")
    drift = float(np.max(np.abs(h["com_vy"] - h["com_vy"][0])))
    check(drift <= 1e-12 * 30.0, f"two rings: total momentum / mass changed by {drift:.3e} m/s")


def crush(scratch: Path) -> None:
    text = ("&run t_end = 1.0e-4, output_dir = 'OUT', end_at_release = .true. /\n"
            "&grid h = 1.0e-3 /\n" + AL + RING.format(y=0.0, v=0.0).replace("'half'", "'quarter'")
            + "&wall point = 0.0, 0.0121, normal = 0.0, -1.0, velocity = 0.0, -10.0 /\n")
    h, s = run(scratch, "crush", text)
    if not h:
        return
    check(abs(h["time"][-1] - 1.0e-4) <= 1e-12, f"crush runs to t_end: {h['time'][-1]:.6e} s")
    check("release" not in str(s.get("message", "")), f"crush: no release ({s.get('message')!r})")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_release")
    scratch.mkdir(parents=True, exist_ok=True)
    ring_on_target(scratch)
    two_rings(scratch)
    crush(scratch)
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
