#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Prove that a change of the code changes no result: run every scene with the binary of a
git reference and with the binary of the work tree, and compare their outputs bit for bit.

Compared: history.csv (the text, byte for byte; where the work tree adds columns, every common
column's text, row by row, and the added columns are named), summary.nml (the value of every
entry but the timings, as plots.mpmplot.namelist reads it, group by group; a group that only
the work tree writes is named, not a difference),
input.nml (byte for byte) and every dataset of particles.h5 (exact equality of the arrays,
NaN equal to NaN). Each binary is the release build, run on one thread. Where only one side
writes the mirror images of a half or quarter model (the subgroup `mirrored` of each snapshot,
docs/output.md: the computed sector followed by its images), its computed-sector part (the
first np rows, the first ncorner rows of `corners`) is compared with the other side's
snapshot datasets, and the images themselves are not compared.

    python3 -m tools.check_identical              # HEAD against the work tree, every scene
    python3 -m tools.check_identical --ref origin/main   # another reference
    python3 -m tools.check_identical --quick 0.1  # each scene to 10 % of its t_end
    python3 -m tools.check_identical --cases namelists/default.nml

Exit 0 when every output is identical, 1 when any differs (each difference is named), 2 on a
usage or build error. Nothing is written into the repository: the reference is built in a
temporary git worktree, the runs go to a temporary folder (--keep DIR keeps them).
"""
import argparse
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

from plots.mpmplot import namelist

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
# summary.nml entries that measure the machine, not the result
TIMING_KEYS = re.compile(r'(wall_seconds|runtime_ratio|updates_per_second|time_\w+|'
                         r'seconds_\w+|\w+_seconds|eta\w*|started|finished|host\w*|'
                         r'binary\w*|version)$', re.IGNORECASE)
DEFAULT_CASES = ['namelists/*.nml', 'tests/scenes/*.nml']


def build(tree, bld, log):
    """Release build of `tree` into its folder `bld`; returns the binary's path."""
    cmd = ['make', '--no-print-directory', '-C', tree, 'BUILD=release', 'BLD=' + bld,
           bld + '/tubempm']
    with open(log, 'w') as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    if rc != 0:
        sys.exit('check_identical: the build of %s failed; see %s' % (tree, log))
    return os.path.join(tree, bld, 'tubempm')


def prepare(case, folder, quick):
    """A copy of the namelist in `folder` with output_dir = 'out' (and t_end scaled)."""
    text = open(case).read()
    values = {'run.output_dir': 'out'}
    t_end = namelist.parse_namelist(text, case)['run'][0].get('t_end')
    if quick and t_end is not None:
        values['run.t_end'] = float(t_end) * quick
    text = namelist.set_values(text, values, case)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, os.path.basename(case))
    with open(path, 'w') as f:
        f.write(text)
    return path


def run(binary, nml, folder):
    env = dict(os.environ, OMP_NUM_THREADS='1')
    with open(os.path.join(folder, 'run.log'), 'w') as f:
        return subprocess.call([binary, '--quiet', os.path.basename(nml)], cwd=folder,
                               stdout=f, stderr=subprocess.STDOUT, env=env)


def summary_groups(path):
    """summary.nml's groups as {name: {entry: value}}, without the timing entries."""
    return {name: {k: v for k, v in entries[-1].items() if not TIMING_KEYS.match(k)}
            for name, entries in namelist.read_namelist(path).items()}


def compare_h5(a, b):
    import h5py
    import numpy as np
    diffs = []
    with h5py.File(a, 'r') as fa, h5py.File(b, 'r') as fb:
        names_a, names_b = [], []
        fa.visit(names_a.append)
        fb.visit(names_b.append)
        for one, other, names in ((fa, fb, names_a), (fb, fa, names_b)):
            for name in [n for n in names if '/mirrored' in n and n not in other]:
                names.remove(name)             # mirror images on one side only
                parent, _, leaf = name.partition('/mirrored')
                leaf = leaf.lstrip('/')
                if not leaf or leaf == 'image' or not isinstance(one[name], h5py.Dataset):
                    continue
                sector = other.get(parent + '/' + leaf)
                if sector is None:
                    diffs.append('particles.h5:%s: no %s/%s to compare with' % (name, parent, leaf))
                    continue
                x, y = one[name][()], sector[()]
                if not np.array_equal(x[:len(y)], y, equal_nan=x.dtype.kind == 'f'):
                    diffs.append('particles.h5:%s: its computed-sector part differs from %s/%s'
                                 % (name, parent, leaf))
        if sorted(names_a) != sorted(names_b):
            diffs.append('particles.h5: different objects: %s vs %s'
                         % (sorted(set(names_a) - set(names_b)), sorted(set(names_b) - set(names_a))))
        for name in sorted(set(names_a) & set(names_b)):
            if not isinstance(fa[name], h5py.Dataset):
                continue
            x, y = fa[name][()], fb[name][()]
            if np.shape(x) != np.shape(y):
                diffs.append('particles.h5:%s: shape %s vs %s' % (name, np.shape(x), np.shape(y)))
                continue
            xa, ya = np.asarray(x), np.asarray(y)
            if xa.dtype.kind == 'f':
                same = np.array_equal(xa.view(np.uint8), ya.view(np.uint8)) or \
                    np.array_equal(xa, ya, equal_nan=True)
            else:
                same = np.array_equal(xa, ya)
            if not same:
                if xa.dtype.kind == 'f':
                    d = np.nanmax(np.abs(xa - ya))
                    diffs.append('particles.h5:%s: differs (largest difference %.3g)' % (name, d))
                else:
                    diffs.append('particles.h5:%s: differs' % name)
    return diffs


def history_columns_added(pa, pb):
    """The columns history.csv gains from a to b when every column of a is in b with the same
    text in every row (None otherwise)."""
    la, lb = open(pa).read().splitlines(), open(pb).read().splitlines()
    if len(la) != len(lb) or not la:
        return None
    ha, hb = la[0].split(','), lb[0].split(',')
    if not set(ha) <= set(hb) or ha == hb:
        return None
    idx = [hb.index(c) for c in ha]
    for ra, rb in zip(la[1:], lb[1:]):
        fa, fb = ra.split(','), rb.split(',')
        if len(fb) != len(hb) or fa != [fb[i] for i in idx]:
            return None
    return [c for c in hb if c not in ha]


def compare(out_a, out_b, notes=None):
    diffs = []
    for name in ('history.csv', 'input.nml'):
        pa, pb = os.path.join(out_a, name), os.path.join(out_b, name)
        if not (os.path.exists(pa) and os.path.exists(pb)):
            diffs.append('%s: missing (%s, %s)' % (name, os.path.exists(pa), os.path.exists(pb)))
            continue
        added = history_columns_added(pa, pb) if name == 'history.csv' else None
        if added is not None:
            if notes is not None:
                notes.append('history.csv: columns added: %s (every other column identical)'
                             % ', '.join(added))
            continue
        if open(pa, 'rb').read() != open(pb, 'rb').read():
            la, lb = open(pa).read().splitlines(), open(pb).read().splitlines()
            first = next((i for i, (x, y) in enumerate(zip(la, lb)) if x != y), min(len(la), len(lb)))
            diffs.append('%s: differs from line %d' % (name, first + 1))
    pa, pb = os.path.join(out_a, 'summary.nml'), os.path.join(out_b, 'summary.nml')
    if os.path.exists(pa) and os.path.exists(pb):
        ga, gb = summary_groups(pa), summary_groups(pb)
        for g in ga:
            sa, sb = ga[g], gb.get(g)
            if sb is None:
                diffs.append('summary.nml: group &%s missing' % g)
                continue
            # repr: a float's shortest exact text, so NaN equals NaN and 0.0 is not -0.0
            keys = [k for k in list(sa) + [k for k in sb if k not in sa]
                    if repr(sa.get(k)) != repr(sb.get(k))]
            if keys:
                diffs.append('summary.nml &%s: differs: %s' % (g, ', '.join(
                    '%s = %r -> %r' % (k, sa.get(k), sb.get(k)) for k in keys[:3])))
        added = [g for g in gb if g not in ga]
        if added:
            if notes is not None:
                notes.append('summary.nml adds ' + ', '.join('&' + g for g in added))
    else:
        diffs.append('summary.nml: missing')
    pa, pb = os.path.join(out_a, 'particles.h5'), os.path.join(out_b, 'particles.h5')
    if os.path.exists(pa) and os.path.exists(pb):
        diffs += compare_h5(pa, pb)
    elif os.path.exists(pa) != os.path.exists(pb):
        diffs.append('particles.h5: present in one run only')
    return diffs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='\n\n'.join(__doc__.split('\n\n')[1:]))
    ap.add_argument('--ref', default='HEAD', help='git reference to compare with (HEAD)')
    ap.add_argument('--cases', nargs='+', default=DEFAULT_CASES,
                    help='namelists or globs (default: namelists/*.nml tests/scenes/*.nml)')
    ap.add_argument('--quick', type=float, default=0.0,
                    help='run each scene to this fraction of its t_end (0 = the whole run)')
    ap.add_argument('--ref-bin', help='use this binary for the reference (no build)')
    ap.add_argument('--new-bin', help='use this binary for the work tree (no build)')
    ap.add_argument('--keep', help='keep the runs in this folder')
    args = ap.parse_args()

    cases = []
    for pat in args.cases:
        found = sorted(glob.glob(os.path.join(ROOT, pat) if not os.path.isabs(pat) else pat))
        if not found:
            sys.exit('check_identical: no namelist matches %s' % pat)
        cases += found
    scratch = args.keep or tempfile.mkdtemp(prefix='tubempm-identical.')
    os.makedirs(scratch, exist_ok=True)
    worktree = None
    try:
        if args.ref_bin:
            ref_bin = os.path.abspath(args.ref_bin)
        else:
            worktree = os.path.join(scratch, 'ref-tree')
            if subprocess.call(['git', '-C', ROOT, 'worktree', 'add', '--detach', '--force',
                                worktree, args.ref], stdout=subprocess.DEVNULL) != 0:
                sys.exit('check_identical: cannot check out %s' % args.ref)
            print('building %s ...' % args.ref, flush=True)
            ref_bin = build(worktree, 'build/identical', os.path.join(scratch, 'build-ref.log'))
        if args.new_bin:
            new_bin = os.path.abspath(args.new_bin)
        else:
            print('building the work tree ...', flush=True)
            new_bin = build(ROOT, 'build/identical', os.path.join(scratch, 'build-new.log'))
        ndiff = 0
        for case in cases:
            rel = os.path.relpath(case, ROOT)
            tag = re.sub(r'[^A-Za-z0-9_.-]', '_', rel)
            outs = []
            codes = []
            for side, binary in (('ref', ref_bin), ('new', new_bin)):
                folder = os.path.join(scratch, side, tag)
                shutil.rmtree(folder, ignore_errors=True)
                nml = prepare(case, folder, args.quick)
                codes.append(run(binary, nml, folder))
                outs.append(os.path.join(folder, 'out'))
            diffs = [] if codes[0] == codes[1] else ['exit status %d vs %d' % tuple(codes)]
            notes = []
            diffs += compare(*outs, notes=notes)
            ndiff += len(diffs) > 0
            print('%-10s %s (exit %d)' % ('IDENTICAL' if not diffs else 'DIFFERENT', rel, codes[1]))
            for d in diffs:
                print('    ' + d)
            for n in notes:
                print('    (' + n + ')')
        print('%d of %d scenes identical' % (len(cases) - ndiff, len(cases)))
        return 1 if ndiff else 0
    finally:
        if worktree:
            subprocess.call(['git', '-C', ROOT, 'worktree', 'remove', '--force', worktree],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if not args.keep:
            shutil.rmtree(scratch, ignore_errors=True)


if __name__ == '__main__':
    sys.exit(main())
