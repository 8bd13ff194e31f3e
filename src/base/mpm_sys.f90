!> Fortran side of the C shim src/base/mpm_sys_c.c: directories and their locks, signals, terminal,
!! rename, the memory available and the cores other work keeps busy (the thread count of a run).
! SPDX-License-Identifier: MIT
module mpm_sys
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_double
  use mpm_kinds, only: wp
  use mpm_strings, only: itoa, plural
  implicit none
  private
  public :: sys_mkdir_p, sys_dir_creatable, sys_lock_dir, sys_install_signals, sys_signal_received, &
            sys_signal_name, sys_stdout_isatty, &
            sys_rename, sys_exit, sys_memory_available, sys_cores_busy, sys_free_threads

  interface
    function c_install_signals() result(r) bind(C, name='tubempm_install_signals')
      import :: c_int
      integer(c_int) :: r
    end function c_install_signals
    function c_signal_received() result(r) bind(C, name='tubempm_signal_received')
      import :: c_int
      integer(c_int) :: r
    end function c_signal_received
    function c_stdout_isatty() result(r) bind(C, name='tubempm_stdout_isatty')
      import :: c_int
      integer(c_int) :: r
    end function c_stdout_isatty
    function c_mkdir_p(path, msg, n) result(r) bind(C, name='tubempm_mkdir_p')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char), intent(out) :: msg(*)
      integer(c_int), value :: n
      integer(c_int) :: r
    end function c_mkdir_p
    function c_dir_creatable(path, msg, n) result(r) bind(C, name='tubempm_dir_creatable')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char), intent(out) :: msg(*)
      integer(c_int), value :: n
      integer(c_int) :: r
    end function c_dir_creatable
    function c_lock_dir(path, msg, n) result(r) bind(C, name='tubempm_lock_dir')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char), intent(out) :: msg(*)
      integer(c_int), value :: n
      integer(c_int) :: r
    end function c_lock_dir
    function c_rename(from, to, msg, n) result(r) bind(C, name='tubempm_rename')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: from(*), to(*)
      character(kind=c_char), intent(out) :: msg(*)
      integer(c_int), value :: n
      integer(c_int) :: r
    end function c_rename
    function c_cores_busy(ms, ncpu) result(r) bind(C, name='tubempm_cores_busy')
      import :: c_int, c_double
      integer(c_int), value :: ms
      integer(c_int), intent(out) :: ncpu
      real(c_double) :: r
    end function c_cores_busy
    subroutine c_exit(code) bind(C, name='tubempm_exit')
      import :: c_int
      integer(c_int), value :: code
    end subroutine c_exit
  end interface

contains

  !> The cores of this process's CPU set and how many of them other work keeps busy, measured
  !! from /proc/stat over `ms` milliseconds while this process sleeps; busy < 0 when unknown.
  subroutine sys_cores_busy(ms, ncpu, busy)
    integer, intent(in) :: ms              !! sampling time [ms]
    integer, intent(out) :: ncpu           !! CPUs this process may run on [-]
    real(wp), intent(out) :: busy          !! cores used by other work, -1 if unknown [-]
    integer(c_int) :: n
    busy = real(c_cores_busy(int(ms, c_int), n), wp)
    ncpu = int(n)
  end subroutine sys_cores_busy

  !> Of nmax threads, as many as there are logical CPUs of this process's CPU set that other
  !! work does not keep busy (at least one), measured over 40 ms (sys_cores_busy; a CPU counts
  !! as busy from half its time on), and no more than a cgroup (v2) CPU quota allows
  !! (cpu.max, rounded up): two threads on two cores of which other work holds one ran at
  !! 0.55-0.72 times one thread (docs/performance.md, Threads). why says what was measured; nmax
  !! when nothing can be measured.
  subroutine sys_free_threads(nmax, n, why)
    integer, intent(in) :: nmax            !! threads wanted [-]
    integer, intent(out) :: n              !! threads to use [-]
    character(len=:), allocatable, intent(out) :: why  !! 'other work keeps B of the C cores busy'
    integer :: ncpu, quota
    real(wp) :: busy
    character(len=16) :: b
    n = nmax
    why = 'not measured'
    if (nmax < 2) return
    quota = cgroup_cpus()
    call sys_cores_busy(40, ncpu, busy)
    if (busy >= 0.0_wp) then
      n = max(1, min(nmax, ncpu - nint(busy)))
      write(b, '(f6.1)') busy
      why = 'other work keeps '//trim(adjustl(b))//' of the '//itoa(ncpu)//' cores busy'
    end if
    if (quota > 0 .and. quota <= n) then   ! the quota binds (named too when both give n)
      n = quota
      why = 'the cgroup CPU quota (/sys/fs/cgroup/cpu.max) allows '//plural(quota, 'core')
    end if
  end subroutine sys_free_threads

  !> The CPUs a cgroup (v2) CPU quota allows, quota/period rounded up (/sys/fs/cgroup/cpu.max,
  !! or the file the environment variable TUBEMPM_CPU_MAX names: tests); 0 when there is no
  !! quota or it cannot be read.
  integer function cgroup_cpus() result(n)
    character(len=64) :: word
    character(len=512) :: path
    real(wp) :: quota, period
    integer :: u, ios, l
    n = 0
    call get_environment_variable('TUBEMPM_CPU_MAX', path, l, ios)
    if (ios /= 0 .or. l == 0) path = '/sys/fs/cgroup/cpu.max'
    open(newunit=u, file=trim(path), status='old', action='read', iostat=ios)
    if (ios /= 0) return
    read(u, *, iostat=ios) word, period
    close(u)
    if (ios /= 0 .or. trim(word) == 'max' .or. .not. period > 0.0_wp) return
    read(word, *, iostat=ios) quota
    if (ios /= 0 .or. .not. quota > 0.0_wp) return
    n = max(1, ceiling(quota/period))
  end function cgroup_cpus

  !> End the program with exit status `code`, printing nothing (every unit is flushed first).
  subroutine sys_exit(code)
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    integer, intent(in) :: code            !! exit status
    flush(output_unit)
    flush(error_unit)
    call c_exit(int(code, c_int))
  end subroutine sys_exit

  !> The memory this process may still take [bytes] and where the number comes from: the
  !! environment variable TUBEMPM_MEMORY_LIMIT (MiB) when set, otherwise MemAvailable of
  !! /proc/meminfo, lowered to what a cgroup (v2) memory limit leaves (memory.max minus
  !! memory.current). known = .false. when none of them can be read (not Linux).
  subroutine sys_memory_available(bytes, source, known)
    real(wp), intent(out) :: bytes         !! memory available [bytes]
    character(len=:), allocatable, intent(out) :: source  !! where the number comes from
    logical, intent(out) :: known          !! a number was found
    character(len=64) :: text
    integer :: n, ios
    real(wp) :: v, limit, used
    bytes = huge(1.0_wp)
    source = ''
    known = .false.
    call get_environment_variable('TUBEMPM_MEMORY_LIMIT', text, n, ios)
    if (ios == 0 .and. n > 0) then
      read(text, *, iostat=ios) v
      if (ios == 0 .and. v > 0.0_wp) then
        bytes = v*1048576.0_wp
        source = 'TUBEMPM_MEMORY_LIMIT'
        known = .true.
        return
      end if
    end if
    v = meminfo_kib('/proc/meminfo', 'MemAvailable:')
    if (v >= 0.0_wp) then
      bytes = 1024.0_wp*v
      source = 'MemAvailable in /proc/meminfo'
      known = .true.
    end if
    limit = file_number('/sys/fs/cgroup/memory.max')
    used = file_number('/sys/fs/cgroup/memory.current')
    if (limit > 0.0_wp .and. used >= 0.0_wp) then
      if (limit - used < bytes) then
        bytes = max(limit - used, 0.0_wp)
        source = 'the cgroup limit /sys/fs/cgroup/memory.max less memory.current'
        known = .true.
      end if
    end if
  end subroutine sys_memory_available

  !> The number (kiB) after `key` in a /proc/meminfo-like file; -1 when not found.
  function meminfo_kib(path, key) result(v)
    character(len=*), intent(in) :: path   !! file
    character(len=*), intent(in) :: key    !! line start, e.g. 'MemAvailable:'
    real(wp) :: v
    character(len=256) :: line
    integer :: u, ios
    v = -1.0_wp
    open(newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, key) == 1) then
        read(line(len(key) + 1:), *, iostat=ios) v
        if (ios /= 0) v = -1.0_wp
        exit
      end if
    end do
    close(u, iostat=ios)
  end function meminfo_kib

  !> The number a one-line file holds; -1 when unreadable or not a number ('max').
  function file_number(path) result(v)
    character(len=*), intent(in) :: path   !! file
    real(wp) :: v
    character(len=64) :: line
    integer :: u, ios
    v = -1.0_wp
    open(newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    read(u, '(a)', iostat=ios) line
    close(u)
    if (ios /= 0) return
    if (verify(trim(adjustl(line)), '0123456789') /= 0 .or. len_trim(line) == 0) return
    read(line, *, iostat=ios) v
    if (ios /= 0) v = -1.0_wp
  end function file_number

  !> Create a directory and its parents; stat = errno (0 ok), errmsg the reason.
  subroutine sys_mkdir_p(path, stat, errmsg)
    character(len=*), intent(in) :: path   !! directory
    integer, intent(out) :: stat           !! 0 or errno
    character(len=:), allocatable, intent(out) :: errmsg  !! reason
    character(kind=c_char) :: msg(512)
    stat = int(c_mkdir_p(to_c(path), msg, 512_c_int))
    errmsg = from_c(msg)
  end subroutine sys_mkdir_p

  !> Whether sys_mkdir_p(path) could make the folder, making nothing: the path or its nearest
  !! existing ancestor is a folder this process can write into; stat = errno (0 yes).
  subroutine sys_dir_creatable(path, stat, errmsg)
    character(len=*), intent(in) :: path   !! directory
    integer, intent(out) :: stat           !! 0 or errno
    character(len=:), allocatable, intent(out) :: errmsg  !! reason
    character(kind=c_char) :: msg(512)
    stat = int(c_dir_creatable(to_c(path), msg, 512_c_int))
    errmsg = from_c(msg)
  end subroutine sys_dir_creatable

  !> Lock a folder for this process until it ends (flock on the folder): stat 0, -1 when
  !! another process holds it, -2 when the file system has no such locks, else errno.
  subroutine sys_lock_dir(path, stat, errmsg)
    character(len=*), intent(in) :: path   !! directory
    integer, intent(out) :: stat           !! 0, -1 (held), -2 (no locks here) or errno (> 0)
    character(len=:), allocatable, intent(out) :: errmsg  !! reason
    character(kind=c_char) :: msg(512)
    stat = int(c_lock_dir(to_c(path), msg, 512_c_int))
    errmsg = from_c(msg)
    if (stat == -2) stat = -1
    if (stat == -3) stat = -2
  end subroutine sys_lock_dir

  !> Rename a file atomically; stat = errno (0 ok).
  subroutine sys_rename(from, to, stat, errmsg)
    character(len=*), intent(in) :: from, to  !! paths
    integer, intent(out) :: stat           !! 0 or errno
    character(len=:), allocatable, intent(out) :: errmsg  !! reason
    character(kind=c_char) :: msg(512)
    stat = int(c_rename(to_c(from), to_c(to), msg, 512_c_int))
    errmsg = from_c(msg)
  end subroutine sys_rename

  !> Install SIGINT/SIGTERM handlers that only set a flag. True on success.
  logical function sys_install_signals() result(ok)
    ok = c_install_signals() == 0
  end function sys_install_signals

  !> The signal number received (0 none).
  integer function sys_signal_received() result(sig)
    sig = int(c_signal_received())
  end function sys_signal_received

  !> A signal as a person knows it: 'SIGINT (Ctrl-C)', 'SIGTERM', else 'signal N'.
  pure function sys_signal_name(sig) result(name)
    integer, intent(in) :: sig             !! the signal number
    character(len=:), allocatable :: name
    select case (sig)
    case (2)
      name = 'SIGINT (Ctrl-C)'
    case (15)
      name = 'SIGTERM'
    case default
      name = 'signal '//itoa(sig)
    end select
  end function sys_signal_name

  !> True when standard output is a terminal.
  logical function sys_stdout_isatty() result(tty)
    tty = c_stdout_isatty() == 1
  end function sys_stdout_isatty

  !> Fortran string to NUL-terminated C array.
  pure function to_c(s) result(c)
    character(len=*), intent(in) :: s      !! text
    character(kind=c_char) :: c(len_trim(s) + 1)
    integer :: i
    do i = 1, len_trim(s)
      c(i) = s(i:i)
    end do
    c(len_trim(s) + 1) = c_null_char
  end function to_c

  !> NUL-terminated C array to Fortran string.
  pure function from_c(c) result(s)
    character(kind=c_char), intent(in) :: c(:)  !! C text
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, size(c)
      if (c(i) == c_null_char) exit
      s = s//c(i)
    end do
  end function from_c
end module mpm_sys
