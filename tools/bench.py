#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Run the fixed benchmark series of `make bench` and report it.

Each configuration (scene, basis, size, threads, deterministic) runs in its own process of the
Fortran driver tools/bench.f90 (release build), which prints one CSV row with the median,
smallest and largest of REPS timed repetitions. The configurations of one scene and size run
interleaved, ROUNDS times over, so that slow drifts of the machine's speed (shared or virtual
machines) hit them alike; the medians are over all ROUNDS x REPS samples. The script prints the
table (particle-steps per second: median and spread), the runtime ratio, the CPDI2 / linear cost
ratio, the two-thread speed-up, the cost of `deterministic`, the phase profile, the fitted cost
exponent and the memory per particle; it writes everything to OUT/bench_<date>.csv and the
plot to OUT/scaling.png. With --compare OLD.csv (an earlier run) it adds the ratio to it.
A run during which other processes used more than a quarter of a core is repeated (up to three
times); the column other_busy keeps the cores they used (the largest over the rounds).
Last, the busy series (issue 16: "no collapse when the other core is busy"): the CPDI2 impact at
about 1e5 particles with 1 and 2 threads and with the automatic count of a run (`&run threads
= 0`), each beside a spinning process on all but one core, interleaved ROUNDS times; its rows go
to OUT/bench_<date>_busy.csv (--no-busy skips it).

With --cost (make bench-cost; never part of make test) it measures instead what --check's
wall-time model needs (tools/advice_tables.py --cost fits it, src/advice/mpm_cost_table.inc):
every shipped namelist (namelists/*.nml, namelists/*/*.nml) and the variants of COST_VARIANTS
on one thread, each its first COST_WORK particle-steps (after 3 untimed steps) in COST_TRIES
processes, the best kept; the cases of COST_FULL (contact that develops during the run) also
once over their whole run. Before and after, the bench's CPDI2 crush at 1e4 particles (the
machine's speed then against make bench's table: its CPDI2 crush at 1e4 particles). Rows to
OUT/cost_<date>.csv.

usage: tools/bench.py --exe build/release/bench [--out out/bench] [--quick] [--tag TAG]
                      [--compare OLD.csv]
       tools/bench.py --exe build/release/bench --cost [--out docs/bench] [--only NAME ...]
"""
import argparse
import csv
import datetime
import glob
import io
import math
import os
import platform
import resource
import statistics
import subprocess
import sys
import time

# scene -> particles through the wall for about 1e4, 3e4, 1e5, 3e5, 1e6 particles
# (2 x 2 particles per cell; crush is a quarter ring, impact a half ring)
SIZES = {"crush": [20, 34, 62, 108, 196], "impact": [16, 28, 50, 88, 160]}
TARGET_PARTICLE_STEPS = 2.0e6      # per repetition
REPS = 3
ROUNDS = 2


def particles(scene, n_thick):
    """Particle count of a bench scene (mpm_particles ring_counts)."""
    r_in, r_out, parts = {"crush": (23.95e-3, 25.43e-3, 4), "impact": (24e-3, 26e-3, 2)}[scene]
    rm = 0.5 * (r_in + r_out)
    n_full = max(4, 4 * int(math.floor(2 * math.pi * rm / ((r_out - r_in) / n_thick) / 4 + 0.5)))
    return n_thick * (n_full // parts)


def groups(quick):
    """Lists of (scene, basis, n_thick, threads, deterministic) run interleaved."""
    out = []
    for scene in ("crush", "impact"):
        sizes = SIZES[scene][:3] if quick else SIZES[scene]
        for k, nt in enumerate(sizes):
            g = [(scene, b, nt, t, 0) for b in ("cpdi2", "linear") for t in (1, 2)]
            if k == 2:                                   # about 1e5 particles: every basis
                g += [(scene, b, nt, t, 0) for b in ("ugimp", "cpdi1") for t in (1, 2)]
            if k == 2 or k == len(sizes) - 1:            # the deterministic scatter
                g += [(scene, "cpdi2", nt, t, 1) for t in (1, 2)]
            out.append(g)
    return out


def busy_cores(seconds=1.0):
    """Cores busy with other work now: non-idle share of /proc/stat over a short window."""
    def sample():
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
        return sum(v), v[3] + v[4]          # total, idle + iowait
    try:
        t0, i0 = sample()
        time.sleep(seconds)
        t1, i1 = sample()
    except OSError:
        return float("nan")
    return (os.cpu_count() or 1) * (1.0 - (i1 - i0) / max(1, t1 - t0))


def cpu_ticks():
    """Non-idle CPU time of the whole machine so far [s] (/proc/stat)."""
    with open("/proc/stat") as f:
        v = [int(x) for x in f.readline().split()[1:]]
    return (sum(v) - v[3] - v[4]) / os.sysconf("SC_CLK_TCK")


def run(exe, header, cfg, tries=3):
    """One process of the bench program; repeated (up to `tries` times) while other work took
    more than a quarter of a core during it. The row gets other_busy: cores used by other work.
    threads 0: the count a run with `&run threads = 0` chooses (no OMP_NUM_THREADS)."""
    scene, basis, nt, threads, det = cfg
    steps = max(5, min(400, int(round(TARGET_PARTICLE_STEPS / particles(scene, nt)))))
    cmd = [exe, scene, basis, str(nt), str(threads), str(steps), str(REPS), str(det)]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    if threads == 0:
        env.pop("OMP_NUM_THREADS")
    best = None
    for _ in range(tries):
        c0, r0, t0 = cpu_ticks(), resource.getrusage(resource.RUSAGE_CHILDREN), time.time()
        out = subprocess.run(cmd, capture_output=True, text=True, env=env)
        c1, r1, t1 = cpu_ticks(), resource.getrusage(resource.RUSAGE_CHILDREN), time.time()
        if out.returncode != 0:
            sys.exit(f"bench: {' '.join(cmd)} failed:\n{out.stderr}")
        mine = (r1.ru_utime + r1.ru_stime) - (r0.ru_utime + r0.ru_stime)
        other = max(0.0, (c1 - c0) - mine) / max(t1 - t0, 1e-9)
        vals = [x.strip() for x in out.stdout.strip().splitlines()[-1].split(",")]
        row = dict(zip(header, vals), other_busy=f"{other:.2f}")
        if best is None or other < float(best["other_busy"]):
            best = row
        if other < 0.25:
            break
    return best


def merge(rows, phases):
    """One row from the rows of several rounds: medians over all samples."""
    r = dict(rows[0])
    samples = [float(x[k]) for x in rows for k in ("mps_median", "mps_min", "mps_max")]
    r["mps_median"] = f"{statistics.median(samples):.5e}"
    r["mps_min"] = f"{min(samples):.5e}"
    r["mps_max"] = f"{max(samples):.5e}"
    for k in ["mps_cpu", "runtime_ratio"] + ["ns_" + p for p in phases]:
        r[k] = f"{statistics.median(float(x[k]) for x in rows):.5g}"
    r["vmhwm_bytes"] = str(max(int(x["vmhwm_bytes"]) for x in rows))
    r["other_busy"] = f"{max(float(x['other_busy']) for x in rows):.2f}"
    r["reps"] = str(sum(int(x["reps"]) for x in rows))
    return r


def fit_exponent(rows):
    """Cost ~ particles^e from a least-squares line through log(time per step)."""
    xs = [math.log(float(r["particles"])) for r in rows]
    ys = [math.log(float(r["particles"]) / float(r["mps_median"])) for r in rows]
    n = len(xs)
    if n < 2:
        return float("nan")
    mx, my = sum(xs) / n, sum(ys) / n
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def key(r):
    return (r["scene"], r["basis"], r["deterministic"], r["threads"], r["particles"])


def report(rows, phases, old):
    def sel(**kw):
        return [r for r in rows if all(str(r[k]) == str(v) for k, v in kw.items())]

    old_by = {key(r): r for r in old}
    print()
    print(f"{'scene':7s} {'basis':6s} {'det':>3s} {'thr':>3s} {'particles':>10s} {'nodes':>9s} "
          f"{'M p-steps/s':>11s} {'spread %':>8s} {'runtime ratio':>13s} {'B/particle':>10s}"
          f" {'other':>5s}" + (f" {'vs old':>7s}" if old else ""))
    for r in rows:
        med, lo, hi = (float(r[k]) for k in ("mps_median", "mps_min", "mps_max"))
        line = (f"{r['scene']:7s} {r['basis']:6s} {r['deterministic']:>3s} {r['threads']:>3s} "
                f"{int(r['particles']):10d} {int(r['nodes']):9d} {med / 1e6:11.3f} "
                f"{100 * (hi - lo) / med:8.1f} {float(r['runtime_ratio']):13.3e} "
                f"{int(r['vmhwm_bytes']) / int(r['particles']):10.0f} "
                f"{float(r.get('other_busy', 'nan')):5.2f}")
        if key(r) in old_by:
            line += f" {med / float(old_by[key(r)]['mps_median']):6.2f}x"
        print(line)

    print("\nphase profile [ns per particle-step], 1 thread, not deterministic")
    print(f"{'scene':7s} {'basis':6s} {'particles':>10s} " + " ".join(f"{p:>8s}" for p in phases)
          + f" {'total':>8s}")
    for r in sel(threads=1, deterministic=0):
        vals = [float(r["ns_" + p]) for p in phases]
        print(f"{r['scene']:7s} {r['basis']:6s} {int(r['particles']):10d} "
              + " ".join(f"{v:8.1f}" for v in vals) + f" {sum(vals):8.1f}")

    print("\nsummary (ratios of medians)")
    for scene in SIZES:
        for basis in ("cpdi2", "linear"):
            for thr in ("1", "2"):
                sub = sel(scene=scene, basis=basis, threads=thr, deterministic=0)
                if len(sub) >= 2:
                    print(f"  {scene:6s} {basis:6s} {thr} thread(s): cost ~ particles^"
                          f"{fit_exponent(sub):.3f} ({int(sub[0]['particles'])} to "
                          f"{int(sub[-1]['particles'])})")
        for c in sel(scene=scene, basis="cpdi2", threads=1, deterministic=0):
            n = c["particles"]
            msg = f"  {scene:6s} {int(n):8d} particles:"
            lin = sel(scene=scene, basis="linear", threads=1, deterministic=0, particles=n)
            two = sel(scene=scene, basis="cpdi2", threads=2, deterministic=0, particles=n)
            d1 = sel(scene=scene, basis="cpdi2", threads=1, deterministic=1, particles=n)
            d2 = sel(scene=scene, basis="cpdi2", threads=2, deterministic=1, particles=n)
            rate = lambda x: float(x[0]["mps_median"])  # noqa: E731
            if lin:
                msg += f" cpdi2/linear time {rate(lin) / rate([c]):.2f},"
            if two:
                msg += f" 2 threads/1 thread speed {rate(two) / rate([c]):.2f},"
            if d1:
                msg += f" deterministic/default time {rate([c]) / rate(d1):.2f} (1 thread)"
            if d2 and two:
                msg += f" {rate(two) / rate(d2):.2f} (2 threads)"
            print(msg.rstrip(","))
    big = max(rows, key=lambda r: int(r["particles"]))
    print(f"  memory at {int(big['particles'])} particles: peak resident "
          f"{int(big['vmhwm_bytes']) / int(big['particles']):.0f} B/particle, modelled "
          f"{int(big['memory_model_bytes']) / int(big['particles']):.0f} B/particle")


def plot(rows, phases, old, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.8), layout="constrained")
    colors = {"cpdi2": "tab:blue", "linear": "tab:orange"}
    for scene, ls in (("crush", "-"), ("impact", "--")):
        for basis in ("cpdi2", "linear"):
            for thr, mk in (("1", "o"), ("2", "s")):
                def pick(rs):
                    return [r for r in rs if r["scene"] == scene and r["basis"] == basis
                            and r["threads"] == thr and r["deterministic"] == "0"]
                sub = pick(rows)
                if sub:
                    x = [int(r["particles"]) for r in sub]
                    y = [float(r["mps_median"]) / 1e6 for r in sub]
                    lo = [y[i] - float(r["mps_min"]) / 1e6 for i, r in enumerate(sub)]
                    hi = [float(r["mps_max"]) / 1e6 - y[i] for i, r in enumerate(sub)]
                    ax.errorbar(x, y, yerr=[lo, hi], color=colors[basis], ls=ls, marker=mk,
                                ms=4, capsize=2, label=f"{scene} {basis} {thr} thr")
                osub = pick(old)
                if osub and scene == "crush":
                    ax.plot([int(r["particles"]) for r in osub],
                            [float(r["mps_median"]) / 1e6 for r in osub], color=colors[basis],
                            ls=":", marker=mk, ms=3, alpha=0.5,
                            label=f"before: {scene} {basis} {thr} thr")
    ax.set_xscale("log")
    ax.set_xlabel("particles [-]")
    ax.set_ylabel("throughput [M particle-steps/s]")
    ax.set_ylim(bottom=0)
    ax.set_title("J2 + MUSL, release build (median, min-max)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6.5, ncol=2, loc="upper left", bbox_to_anchor=(0.0, -0.14))

    sub = [r for r in rows if r["threads"] == "1" and r["deterministic"] == "0"
           and r["basis"] in ("cpdi2", "linear")]
    labels = [f"{r['scene'][:2]} {r['basis'][:3]} {int(r['particles']) / 1e3:.0f}k" for r in sub]
    bottom = [0.0] * len(sub)
    cmap = plt.get_cmap("viridis")
    for k, p in enumerate(phases):
        v = [float(r["ns_" + p]) for r in sub]
        bx.bar(labels, v, bottom=bottom, color=cmap(k / max(1, len(phases) - 1)), label=p)
        bottom = [b + x for b, x in zip(bottom, v)]
    bx.set_ylabel("time per particle-step [ns]")
    bx.set_title("phase profile, 1 thread")
    bx.tick_params(axis="x", labelrotation=70, labelsize=6.5)
    bx.set_ylim(0, 1.25 * max(bottom))
    bx.legend(fontsize=7, ncol=4, loc="upper left")
    fig.savefig(path, dpi=150)
    plt.close(fig)


def busy_series(exe, header, phases):
    """The CPDI2 impact at about 1e5 particles beside a spinning process on all but one core:
    1 thread, 2 threads, and the automatic count (threads 0), interleaved ROUNDS times."""
    ncpu = len(os.sched_getaffinity(0))
    if ncpu < 2:
        return []
    cfgs = [("impact", "cpdi2", SIZES["impact"][2], t, 0) for t in (1, 2, 0)]
    spin = [subprocess.Popen([sys.executable, "-c", "while True: pass"])
            for _ in range(ncpu - 1)]
    try:
        time.sleep(0.5)
        got = {cfg: [] for cfg in cfgs}
        for _ in range(ROUNDS):
            for cfg in cfgs:
                got[cfg].append(run(exe, header, cfg, tries=1))
    finally:
        for p in spin:
            p.kill()
            p.wait()
    rows = []
    for cfg in cfgs:
        r = merge(got[cfg], phases)
        r["threads_asked"] = str(cfg[3])
        rows.append(r)
    one = float(rows[0]["mps_median"])
    print(f"\nbusy series: impact cpdi2 {int(rows[0]['particles'])} particles beside "
          f"{ncpu - 1} spinning process(es)")
    for r in rows:
        asked = "auto" if r["threads_asked"] == "0" else r["threads_asked"]
        print(f"  threads {asked:>4s} (ran {r['threads']}): "
              f"{float(r['mps_median']) / 1e6:6.3f} M particle-steps/s, "
              f"{float(r['mps_median']) / one:5.2f} x one thread, other work "
              f"{float(r['other_busy']):.2f} cores")
    return rows


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
COST_WORK = 1.5e7      # particle-steps of a case's first segment
COST_TRIES = 3         # processes per case: the best (the least disturbed) is kept
# contact between bodies that starts after t = 0 and grows (its mean over the whole run)
# (and the foam, whose return map costs more once it yields), each once over its whole run
COST_FULL = ("contact/nested", "contact/two_rings", "contact/plates", "contact/row3",
             "contact/densify", "foam/filled_ring", "contact/nested_eccentric", "contact/stack",
             "foam/foam_block", "foam/foam_disc", "foam/foam_square", "foam/filled_drop")
# controlled variants (name: namelist, values set): a term alone; foam_square_j2 (a J2 core
# that yields from the first steps: J2's return map is no term of the model) is measured, not
# fitted (COST_CONTROLS)
COST_CONTROLS = ("variant/foam_square_j2",)
COST_VARIANTS = {
    "variant/hex_tube_no_self": ("sections/hex_tube", {"body.self_contact": False}),
    "variant/honeycomb_no_self": ("sections/honeycomb", {"body.self_contact": False}),
    "variant/foam_square_j2": ("foam/foam_square", {"material.model": "j2", "material.sigma_y":
                                                    1.6e6, "material.hardening": 2.0e6}),
}


def write_variant(name, folder):
    """Write the namelist of a variant of COST_VARIANTS into folder; its path."""
    from plots.mpmplot import namelist
    base, values = COST_VARIANTS[name]
    with open(os.path.join(ROOT, "namelists", base + ".nml")) as f:
        text = namelist.set_values(f.read(), values)
    path = os.path.join(folder, os.path.basename(name) + ".nml")
    with open(path, "w") as f:
        f.write(text)
    return path


def cost_cases(only):
    """(name, path of the namelist to run, whole run?) of every case of --cost."""
    nml = os.path.join(ROOT, "namelists")
    names = sorted(os.path.relpath(os.path.join(d, f), nml)[:-4]
                   for d, _, fs in os.walk(nml) for f in fs if f.endswith(".nml"))
    out = [(n, os.path.join(nml, n + ".nml"), False) for n in names]
    tmp = os.path.join(ROOT, "out", "bench", "cost_variants")
    os.makedirs(tmp, exist_ok=True)
    for name in COST_VARIANTS:
        out.append((name, write_variant(name, tmp), False))
    out += [(n, os.path.join(nml, n + ".nml"), True) for n in COST_FULL]
    return [c for c in out if not only or c[0] in only]


def steps_to_end(path):
    """The steps --check counts to t_end (at the initial speeds)."""
    out = subprocess.run([os.path.join(ROOT, "bin", "tubempm"), "--check", path],
                         capture_output=True, text=True)
    for line in out.stdout.splitlines():
        if line.startswith("steps: about") and "(" in line:
            return int(line.split("(")[1].split()[0])
    sys.exit(f"bench: --check {path} gave no step count:\n{out.stdout}{out.stderr}")


def cost_run(exe, header, name, path, full):
    """One case on one thread: its first segment (best of COST_TRIES processes) or its whole
    run (one process, 25 segments). The row of `bench case` (columns `header`) with the case's
    name."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    total = steps_to_end(path)
    if full:
        cmd = [exe, "case", path, "1", str((total + 24) // 25), "25", "0"]
        tries = 1
    else:
        probe = subprocess.run([exe, "case", path, "1", "1", "1", "0"], capture_output=True,
                               text=True, env=env)
        if probe.returncode != 0:
            sys.exit(f"bench: {path}: {probe.stderr}")
        np_ = int(dict(zip(header, probe.stdout.strip().split(",")))["particles"])
        steps = max(50, min(total - 3, int(COST_WORK / np_)))
        cmd = [exe, "case", path, "1", str(steps), "1", "3"]
        tries = COST_TRIES
    best = None
    for _ in range(tries):
        out = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if out.returncode != 0:
            sys.exit(f"bench: {' '.join(cmd)} failed:\n{out.stderr}")
        row = out.stdout.strip().splitlines()[-1].split(",")
        best_col = header.index("mps_all")      # (the rate the fit reads)
        if best is None or float(row[best_col]) > float(best[best_col]):
            best = row
    best[0] = name
    return ["run" if full else "first"] + best


def reference_rate(exe):
    """The bench's CPDI2 crush at about 1e4 particles on one thread (the size of the shipped
    scenes: a working set in cache like theirs), best of COST_TRIES [particle-steps/s]: the
    machine's speed now, against make bench's table."""
    cfg = ("crush", "cpdi2", SIZES["crush"][0], 1, 0)
    return max(float(run(exe, subprocess.run([exe, "--header"], capture_output=True, text=True,
                                             check=True).stdout.strip().split(","), cfg)
                     ["mps_median"]) for _ in range(COST_TRIES))


def cost_main(args):
    header = subprocess.run([args.exe, "--case-header"], capture_output=True, text=True,
                            check=True).stdout.strip().split(",")
    stamp = datetime.datetime.now().strftime("%Y-%m-%d_%H%M")
    t0 = time.time()
    ref0 = reference_rate(args.exe)
    print(f"reference (crush cpdi2 1e4, 1 thread): {ref0 / 1e6:.3f} M particle-steps/s", flush=True)
    rows = []
    for name, path, full in cost_cases(args.only):
        r = cost_run(args.exe, header, name, path, full)
        rows.append(r)
        d = dict(zip(["segment"] + header, r))
        print(f"{d['segment']:5s} {name:36s} {int(d['particles']):6d} particles, "
              f"{float(d['mps_all']) / 1e6:6.3f} M particle-steps/s, "
              f"{float(d['pair_entries']):7.1f} pair entries", flush=True)
    ref1 = reference_rate(args.exe)
    print(f"reference after: {ref1 / 1e6:.3f} M particle-steps/s; {time.time() - t0:.0f} s in all")
    for r in rows:                      # each row with the reference of its measurement
        r.append(f"{0.5 * (ref0 + ref1):.5e}")
    header = ["segment"] + header + ["reference_mps"]
    old = sorted(glob.glob(os.path.join(args.out, "cost_*.csv")))
    if args.only and old:               # the rows not measured now: the newest table's
        done = {(r[0], r[1]) for r in rows}
        with open(old[-1]) as f:
            kept = [r for r in csv.reader(line for line in f if not line.startswith("#"))][1:]
        rows = [r for r in kept if (r[0], r[1]) not in done] + rows
        print(f"rows of {os.path.basename(old[-1])} kept: {len(kept) - len(done & {(r[0], r[1]) for r in kept})}")
    os.makedirs(args.out, exist_ok=True)
    name = os.path.join(args.out, f"cost_{stamp}{'_' + args.tag if args.tag else ''}.csv")
    with open(name, "w") as f:
        f.write(f"# tubempm make bench-cost, {stamp}, {platform.node()}, one thread; "
                f"reference_mps: the bench's CPDI2 crush at {SIZES['crush'][0]} particles "
                f"through the wall, mean of before and after the row's series "
                f"({'these cases' if args.only else 'all'}: {ref0:.5e} / {ref1:.5e})\n")
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)
    print(f"table written to {name}")


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", required=True, help="the bench program (release build)")
    ap.add_argument("--out", default="out/bench", help="folder for the CSV file and the plot "
                    "(default out/bench; make bench writes docs/bench)")
    ap.add_argument("--quick", action="store_true", help="sizes up to 1e5 particles only")
    ap.add_argument("--tag", default="", help="label added to the file names")
    ap.add_argument("--compare", default="", help="an earlier CSV file to compare with")
    ap.add_argument("--no-plot", action="store_true", help="skip the PNG")
    ap.add_argument("--no-busy", action="store_true", help="skip the busy series")
    ap.add_argument("--cost", action="store_true", help="the cost model's measurements "
                    "(make bench-cost): every shipped namelist on one thread")
    ap.add_argument("--only", nargs="*", default=[], help="with --cost: these cases only "
                    "(names as contact/nested)")
    args = ap.parse_args()
    if args.cost:
        cost_main(args)
        return

    header = subprocess.run([args.exe, "--header"], capture_output=True, text=True,
                            check=True).stdout.strip().split(",")
    phases = [h[3:] for h in header if h.startswith("ns_")]
    old = read_csv(args.compare) if args.compare else []
    busy0 = busy_cores()
    print(f"tubempm benchmark: {platform.node()}, {os.cpu_count()} cores, {busy0:.2f} cores "
          f"busy with other work, OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', '(unset)')}"
          f", OMP_PROC_BIND={os.environ.get('OMP_PROC_BIND', '(unset)')}")
    if busy0 > 0.2:
        print("WARNING: other work is running; timings will be low and noisy, two-thread "
              "ones much lower (a thread waits at every barrier for the shared core)")
    t0 = time.time()
    rows = []
    gs = groups(args.quick)
    for i, g in enumerate(gs, 1):
        got = {cfg: [] for cfg in g}
        for _ in range(ROUNDS):
            for cfg in g:
                got[cfg].append(run(args.exe, header, cfg))
        for cfg in g:
            r = merge(got[cfg], phases)
            rows.append(r)
            print(f"[{i:2d}/{len(gs)}] {cfg[0]:6s} {cfg[1]:6s} det={cfg[4]} threads={cfg[3]} "
                  f"{int(r['particles']):8d} particles: {float(r['mps_median']) / 1e6:6.3f} "
                  f"M particle-steps/s", flush=True)
    busy1 = busy_cores()
    report(rows, phases, old)
    busy_rows = [] if args.no_busy else busy_series(args.exe, header, phases)
    print(f"\ncores busy with other work before {busy0:.2f}, after {busy1:.2f}; "
          f"{time.time() - t0:.0f} s in all")
    os.makedirs(args.out, exist_ok=True)
    stamp = datetime.datetime.now().strftime("%Y-%m-%d_%H%M")
    tag = "_" + args.tag if args.tag else ""
    name = os.path.join(args.out, f"bench_{stamp}{tag}.csv")
    with open(name, "w") as f:
        f.write(f"# tubempm make bench, {stamp}, {platform.node()}, {os.cpu_count()} cores, "
                f"busy with other work {busy0:.2f} / {busy1:.2f} cores (before / after)\n")
        w = csv.DictWriter(f, fieldnames=header + ["other_busy"], lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    print(f"table written to {name}")
    if busy_rows:
        bname = os.path.join(args.out, f"bench_{stamp}{tag}_busy.csv")
        with open(bname, "w") as f:
            f.write(f"# tubempm make bench, busy series, {stamp}, {platform.node()}: a "
                    f"spinning process on all but one core; threads_asked 0 = automatic\n")
            w = csv.DictWriter(f, fieldnames=header + ["other_busy", "threads_asked"],
                               lineterminator="\n")
            w.writeheader()
            w.writerows(busy_rows)
        print(f"busy series written to {bname}")
    if not args.no_plot:
        png = os.path.join(args.out, f"scaling{tag}.png")
        plot(rows, phases, old, png)
        print(f"plot written to {png}")


if __name__ == "__main__":
    main()
