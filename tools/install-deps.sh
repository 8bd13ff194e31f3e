#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Install what tubempm needs and is missing: Debian packages (gfortran, HDF5 Fortran, pkg-config)
# and the Python packages of plots/requirements.txt. Idempotent; silent when all is present.
# Without root it prints the exact commands to run by hand and exits 2.
#   usage: tools/install-deps.sh [--python-only|--fortran-only|--paraview|--ccx|--slurm]
#   --paraview: only ParaView with its Python (pvbatch) and a virtual display (xvfb), for
#   `make check-paraview`
#   --ccx: also CalculiX's solver ccx (Debian package calculix-ccx), for `make fe-reference`
#   --slurm: also Slurm (Debian's slurm-wlm: slurmctld, slurmd, sbatch, squeue, scancel) and
#   munge, for `make test-slurm`
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
want_fortran=1; want_python=1; want_ccx=0; want_slurm=0
want_paraview=0
case "${1:-}" in
  --paraview) want_fortran=0; want_python=0; want_paraview=1 ;;
  --python-only) want_fortran=0 ;;
  --fortran-only) want_python=0 ;;
  --ccx) want_fortran=0; want_ccx=1 ;;
  --slurm) want_fortran=0; want_slurm=1 ;;
  "") ;;
  -h|--help) awk 'NR > 2 && /^#/ {sub(/^# ?/, ""); print; next} NR > 2 {exit}' "$0"; exit 0 ;;
  *) echo "usage: $0 [--python-only|--fortran-only|--paraview|--ccx|--slurm]" >&2; exit 2 ;;
esac

missing_deb=()
if [ $want_fortran = 1 ]; then
  command -v gfortran >/dev/null 2>&1 || missing_deb+=(gfortran)
  command -v pkg-config >/dev/null 2>&1 || missing_deb+=(pkg-config)
  command -v make >/dev/null 2>&1 || missing_deb+=(make)
  hdf5_ok=0
  if pkg-config --exists hdf5 2>/dev/null; then
    # the Fortran library sits in a -L directory; the module file in an -I directory
    for d in $(pkg-config --libs-only-L hdf5 | sed 's/-L//g') /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib; do
      if [ -e "$d/libhdf5_fortran.so" ]; then
        for inc in $(pkg-config --cflags-only-I hdf5 | sed 's/-I//g') /usr/include; do
          [ -e "$inc/hdf5.mod" ] && hdf5_ok=1
        done
      fi
    done
  fi
  [ $hdf5_ok = 1 ] || missing_deb+=(libhdf5-dev)
fi
if [ $want_paraview = 1 ]; then
  command -v pvbatch >/dev/null 2>&1 || missing_deb+=(paraview)
  [ -e /usr/lib/python3/dist-packages/paraview ] || command -v pvpython >/dev/null 2>&1 \
    || missing_deb+=(python3-paraview)
  command -v xvfb-run >/dev/null 2>&1 || missing_deb+=(xvfb xauth)
fi
if [ $want_ccx = 1 ]; then
  # the FE reference was made with ccx 2.20 (Debian 12's calculix-ccx); another version runs
  # but may give a slightly different curve
  command -v ccx >/dev/null 2>&1 || missing_deb+=(calculix-ccx)
fi
if [ $want_slurm = 1 ]; then
  # the daemons live in /usr/sbin, which a non-root PATH may lack
  for c in slurmctld slurmd; do
    command -v $c >/dev/null 2>&1 || [ -x /usr/sbin/$c ] || { missing_deb+=(slurm-wlm); break; }
  done
  command -v sbatch >/dev/null 2>&1 || [[ " ${missing_deb[*]} " == *" slurm-wlm "* ]] \
    || missing_deb+=(slurm-wlm)
  command -v munged >/dev/null 2>&1 || [ -x /usr/sbin/munged ] || missing_deb+=(munge)
fi
py=${PYTHON:-python3}
missing_py=()
if [ $want_python = 1 ]; then
  command -v "$py" >/dev/null 2>&1 || missing_deb+=(python3)
  for mod in numpy matplotlib h5py; do
    "$py" -c "import $mod" >/dev/null 2>&1 || missing_py+=("$mod")
  done
  if [ ${#missing_py[@]} -gt 0 ] && ! "$py" -m pip --version >/dev/null 2>&1; then
    missing_deb+=(python3-pip)
  fi
fi

[ ${#missing_deb[@]} -eq 0 ] && [ ${#missing_py[@]} -eq 0 ] && exit 0

sudo=""
if [ "$(id -u)" != 0 ]; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then sudo="sudo -n"; else sudo=NONE; fi
fi

if [ ${#missing_deb[@]} -gt 0 ]; then
  if [ "$sudo" = NONE ] || ! command -v apt-get >/dev/null 2>&1; then
    echo "tubempm needs these system packages, which this script cannot install here:" >&2
    echo "    sudo apt-get install -y ${missing_deb[*]}" >&2
    echo "(on other systems: gfortran, the HDF5 Fortran library with pkg-config file, python3-pip;" >&2
    echo " for make fe-reference: CalculiX 2.20's ccx on PATH, from www.calculix.de)" >&2
    [ ${#missing_py[@]} -gt 0 ] && \
      echo "and the Python packages:  python3 -m pip install -r $here/plots/requirements.txt" >&2
    exit 2
  fi
  echo "install-deps: installing Debian packages: ${missing_deb[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq >/dev/null || { echo "install-deps: apt-get update failed" >&2; exit 2; }
  $sudo apt-get install -y -qq --no-install-recommends "${missing_deb[@]}" >/dev/null \
    || { echo "install-deps: apt-get install ${missing_deb[*]} failed" >&2; exit 2; }
fi

if [ ${#missing_py[@]} -gt 0 ]; then
  echo "install-deps: installing Python packages: ${missing_py[*]}"
  pipflags="-q"
  # Debian's own python3 refuses system-wide pip installs (PEP 668) unless told otherwise.
  if "$py" -c 'import sys,sysconfig,os; sys.exit(0 if os.path.exists(os.path.join(sysconfig.get_paths()["stdlib"],"EXTERNALLY-MANAGED")) else 1)' 2>/dev/null; then
    pipflags="$pipflags --break-system-packages"
  fi
  if [ "$(id -u)" != 0 ] && [ -z "${VIRTUAL_ENV:-}" ]; then pipflags="$pipflags --user"; fi
  if ! PIP_ROOT_USER_ACTION=ignore PIP_DISABLE_PIP_VERSION_CHECK=1 \
       "$py" -m pip install $pipflags -r "$here/plots/requirements.txt"; then
    # Debian's own python3 can take the same libraries from Debian's packages instead
    if [ "$(command -v "$py")" = /usr/bin/python3 ] && [ "$sudo" != NONE ] && command -v apt-get >/dev/null 2>&1 \
       && $sudo apt-get install -y -qq python3-numpy python3-matplotlib python3-h5py >/dev/null; then
      echo "install-deps: pip failed; installed python3-numpy python3-matplotlib python3-h5py with apt-get"
    else
      echo "install-deps: pip install failed; run by hand: $py -m pip install -r $here/plots/requirements.txt" >&2
      echo "  (or on Debian: sudo apt-get install python3-numpy python3-matplotlib python3-h5py)" >&2
      exit 2
    fi
  fi
fi
exit 0
