!> tubempm: material point method for thin-walled tubes under lateral compression.
! SPDX-License-Identifier: MIT
!
!   bin/tubempm CASE.nml | --check CASE.nml | --restart DIR | --defaults | --help | --version
!   [--quiet]
! The driver is the only place that stops the program (exit codes of shared/INTERFACE.md).
program tubempm
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, compiler_version, &
                                           compiler_options
  !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: version_string, EXIT_INPUT, EXIT_IO, path_len
  use mpm_errors, only: fatal, warn
  use mpm_config, only: config_t, read_config, write_config, write_config_unit, default_config
  use mpm_setup, only: setup_sim, setup_report, sector_factor
  use mpm_advice, only: study_advice, advice_end_of_run
  use mpm_solver, only: sim_t, solver_step
  use mpm_particles, only: particles_t
  use mpm_output, only: history_t, history_open, history_write, history_close, write_summary, &
                        summary_t
  use mpm_io_hdf5, only: snapfile_t, snap_create, snap_reopen, snap_write, snap_close, xdmf_write
  use mpm_restart, only: checkpoint_write, checkpoint_read, ckpt_extra_t
  use mpm_sys, only: sys_mkdir_p, sys_install_signals, sys_signal_received, sys_stdout_isatty
  use mpm_strings, only: itoa, rtoa
  implicit none

  character(len=path_len) :: case_file, arg, restart_dir
  logical :: check_only, quiet, restart
  integer :: i, nargs, stat
  character(len=:), allocatable :: errmsg, report, warnings, input_warnings, advice
  type(config_t) :: cfg
  type(sim_t) :: s

  ! command line
  check_only = .false.
  quiet = .false.
  restart = .false.
  case_file = ''
  nargs = command_argument_count()
  i = 0
  do while (i < nargs)
    i = i + 1
    call get_command_argument(i, arg)
    select case (trim(arg))
    case ('--help', '-h')
      call print_help()
      stop
    case ('--version')
      write(output_unit, '(a)') 'tubempm '//version_string
      write(output_unit, '(a)') 'compiler: '//compiler_version()
      write(output_unit, '(a)') 'options:  '//compiler_options()
      stop
    case ('--defaults')
      call default_config(cfg)
      call write_config_unit(cfg, output_unit, stat, errmsg)
      if (stat /= 0) call fatal('defaults', errmsg, EXIT_IO)
      stop
    case ('--check')
      check_only = .true.
    case ('--quiet', '-q')
      quiet = .true.
    case ('--restart')
      restart = .true.
      if (i == nargs) call fatal('command line', '--restart needs the output folder of the '// &
        'run to continue. Usage: tubempm --restart DIR', EXIT_INPUT)
      i = i + 1
      call get_command_argument(i, restart_dir)
    case default
      if (arg(1:1) == '-') then
        call fatal('command line', 'unknown option '''//trim(arg)//'''. Usage: tubempm '// &
          '[--check] [--quiet] CASE.nml | --restart DIR | --defaults | --help | --version', &
          EXIT_INPUT)
      end if
      if (len_trim(case_file) > 0) call fatal('command line', 'more than one case file ('// &
        trim(case_file)//', '//trim(arg)//'). Usage: tubempm [--check] [--quiet] CASE.nml', &
        EXIT_INPUT)
      case_file = arg
    end select
  end do
  if (restart) then
    if (len_trim(case_file) > 0) call fatal('command line', '--restart DIR takes no case '// &
      'file: the case is DIR/input.nml. Usage: tubempm --restart DIR', EXIT_INPUT)
    case_file = trim(restart_dir)//'/input.nml'
  end if
  if (len_trim(case_file) == 0) call fatal('command line', 'no case file given. Usage: '// &
    'tubempm [--check] [--quiet] CASE.nml | --restart DIR | --help', EXIT_INPUT)

  ! input, set-up, report
  call read_config(case_file, cfg, stat, errmsg, input_warnings, advice)   ! advice: once, below
  if (stat /= 0) call fatal('input', errmsg, stat)
  if (restart) cfg%run%output_dir = restart_dir
  if (len(input_warnings) > 0) call print_warnings(input_warnings)
  call setup_sim(cfg, s, stat, errmsg)
  if (stat /= 0) call fatal('input', errmsg, stat)
  if (cfg%run%threads > 0) then
    !$ call omp_set_num_threads(cfg%run%threads)
  end if
  call setup_report(cfg, s, report, warnings)
  if (check_only .or. .not. quiet) then
    write(output_unit, '(a)') report
    flush(output_unit)
  end if
  if (len(warnings) > 0) call print_warnings(warnings)
  if (check_only) then
    call study_advice(cfg, s%g%h, advice)
    if (len(advice) > 0) write(output_unit, '(a)') advice
    write(output_unit, '(a)') 'input ok: '//trim(case_file)
    stop
  end if
  call run_case(cfg, s, quiet, restart)

contains

  subroutine print_help()
    write(output_unit, '(a)') 'tubempm '//version_string// &
      ': material point method (CPDI) for thin-walled tubes under lateral compression'
    write(output_unit, '(a)') ''
    write(output_unit, '(a)') 'usage:'
    write(output_unit, '(a)') '  tubempm CASE.nml             run the case (outputs in &run output_dir)'
    write(output_unit, '(a)') '  tubempm --check CASE.nml     validate; print the derived set-up and exit'
    write(output_unit, '(a)') '  tubempm --restart DIR        continue the run in DIR from its last checkpoint'
    write(output_unit, '(a)') '  tubempm --defaults           print every namelist group with its defaults'
    write(output_unit, '(a)') '  tubempm --help | --version'
    write(output_unit, '(a)') '  --quiet                      no progress line (errors and warnings still printed)'
    write(output_unit, '(a)') ''
    write(output_unit, '(a)') 'exit status: 0 ok, 1 internal error, 2 bad input, 3 I/O failure,'
    write(output_unit, '(a)') '             4 numerical failure, 5 interrupted (checkpoint written)'
    write(output_unit, '(a)') 'input: docs/input.md; outputs: docs/output.md'
  end subroutine print_help

  subroutine print_warnings(text)
    character(len=*), intent(in) :: text
    integer :: i0, i1
    i0 = 1
    do
      i1 = index(text(i0:), new_line('a'))
      if (i1 == 0) then
        call warn('check', text(i0:))
        exit
      end if
      call warn('check', text(i0:i0 + i1 - 2))
      i0 = i0 + i1
    end do
  end subroutine print_warnings

  !> Index of the particle nearest to each probe point at t = 0.
  function probe_particles(cfg, s) result(idx)
    type(config_t), intent(in) :: cfg
    type(sim_t), intent(in) :: s
    integer, allocatable :: idx(:)
    integer :: k, ip
    real(wp) :: d, dbest
    allocate(idx(size(cfg%probes)))
    do k = 1, size(cfg%probes)
      dbest = huge(1.0_wp)
      idx(k) = 1
      do ip = 1, s%p%np
        d = sum((s%p%x(:, ip) - cfg%probes(k)%point)**2)
        if (d < dbest) then
          dbest = d
          idx(k) = ip
        end if
      end do
    end do
  end function probe_particles

  !> The time loop with outputs, progress, checkpoints, failure and signal handling.
  subroutine run_case(cfg, s, quiet, restart)
    type(config_t), intent(inout) :: cfg
    type(sim_t), intent(inout) :: s
    logical, intent(in) :: quiet, restart
    character(len=:), allocatable :: dir, msg, input_text
    type(history_t) :: hist
    type(snapfile_t) :: snaps
    type(summary_t) :: sm
    type(particles_t) :: good
    type(ckpt_extra_t) :: ex
    real(wp) :: t_good, dt_good, next_snap, last_progress, elapsed, last_ckpt, seconds0
    integer(i8) :: step_good, c0, c1, crate
    integer :: st, sig
    logical :: tty
    integer, parameter :: backup_every = 50
    integer, allocatable :: probes(:)

    dir = trim(cfg%run%output_dir)
    seconds0 = 0.0_wp
    probes = probe_particles(cfg, s)         ! nearest particles at t = 0 (before a restart)
    if (restart) then
      input_text = read_text(dir//'/input.nml')
      call checkpoint_read(dir, input_text, s, ex, st, msg)
      if (st == 2) call fatal('restart', msg, EXIT_INPUT)
      if (st /= 0) call fatal('restart', msg, EXIT_IO)
      seconds0 = ex%wall_seconds
      call history_truncate(dir//'/history.csv', ex%history_rows, st, msg)
      if (st /= 0) call fatal('restart', msg, EXIT_IO)
      call history_open(hist, dir//'/history.csv', s, cfg%run%history_every, cfg%run%depth, &
                        sector_factor(cfg), probes, st, msg, append=.true.)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      hist%rows = ex%history_rows
      hist%next_time = ex%history_next
      hist%last_time = ex%history_last
      call snap_reopen(snaps, dir//'/particles.h5', ex%snap_times, ex%snap_np, ex%snap_nc, st, &
                       msg)
      if (st /= 0) call fatal('restart', msg, EXIT_IO)
      next_snap = ex%snapshot_next
      if (.not. quiet) write(output_unit, '(a)') 'restarting from the checkpoint at t = '// &
        rtoa(s%t)//' s, step '//itoa(s%step)
    else
      call sys_mkdir_p(dir, st, msg)
      if (st /= 0) call fatal('output', 'cannot create the output folder '//dir//': '//msg// &
        '. Choose a writable &run output_dir', EXIT_IO)
      call write_config(cfg, dir//'/input.nml', st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      input_text = read_text(dir//'/input.nml')
      call history_open(hist, dir//'/history.csv', s, cfg%run%history_every, cfg%run%depth, &
                        sector_factor(cfg), probes, st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      call snap_create(snaps, dir//'/particles.h5', input_text, st, msg)
      if (st /= 0) call fatal('output', msg//' ('//dir//'/particles.h5)', EXIT_IO)
      call history_write(hist, s, .true., st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      call snap_write(snaps, s%p, s%basis, s%t, s%step, s%dt, st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      call xdmf_write(snaps, dir//'/particles.xdmf', 'particles.h5', st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      next_snap = cfg%run%snapshot_every
    end if
    if (.not. sys_install_signals()) call warn('run', 'could not install signal handlers')
    sm%threads = 1
    !$ sm%threads = omp_get_max_threads()
    good = s%p
    t_good = s%t
    dt_good = s%dt
    step_good = s%step
    tty = sys_stdout_isatty()
    call system_clock(c0, crate)
    last_progress = 0.0_wp
    last_ckpt = 0.0_wp
    sig = 0

    do while (s%t < s%t_end)
      call solver_step(s, st, msg)
      if (st /= 0) then
        call system_clock(c1)
        sm%wall_seconds = seconds0 + real(c1 - c0, wp)/real(crate, wp)
        call on_failure(st, msg, dir, input_text, s, good, t_good, dt_good, step_good, snaps, &
                        hist, sm)
      end if
      call history_write(hist, s, s%t >= s%t_end, st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      if (cfg%run%snapshot_every > 0.0_wp .and. s%t >= next_snap*(1.0_wp - 1.0e-12_wp) &
          .and. s%t < s%t_end) then
        call snap_write(snaps, s%p, s%basis, s%t, s%step, s%dt, st, msg)
        if (st /= 0) call fatal('output', msg, EXIT_IO)
        call xdmf_write(snaps, dir//'/particles.xdmf', 'particles.h5', st, msg)
        if (st /= 0) call fatal('output', msg, EXIT_IO)
        do while (next_snap <= s%t*(1.0_wp + 1.0e-12_wp))
          next_snap = next_snap + cfg%run%snapshot_every
        end do
      end if
      if (mod(s%step, int(backup_every, i8)) == 0_i8) then
        good = s%p
        t_good = s%t
        dt_good = s%dt
        step_good = s%step
      end if
      call system_clock(c1)
      elapsed = real(c1 - c0, wp)/real(crate, wp)
      if (.not. quiet .and. (elapsed - last_progress > merge(0.5_wp, 10.0_wp, tty))) then
        call progress(s, elapsed, tty)
        last_progress = elapsed
      end if
      sig = sys_signal_received()
      if (sig /= 0 .or. (cfg%run%checkpoint_every > 0.0_wp .and. &
                         elapsed - last_ckpt >= cfg%run%checkpoint_every)) then
        ! checkpoint with the output positions; an I/O failure here stops the run (exit 3)
        ex%history_rows = hist%rows
        ex%history_next = hist%next_time
        ex%history_last = hist%last_time
        ex%snapshot_next = next_snap
        ex%snap_times = snaps%times
        ex%snap_np = snaps%nps
        ex%snap_nc = snaps%ncs
        ex%wall_seconds = seconds0 + elapsed
        call checkpoint_write(dir, input_text, s, ex, st, msg)
        if (st /= 0) call fatal('checkpoint', msg, EXIT_IO)
        last_ckpt = elapsed
      end if
      if (sig /= 0) then
        sm%status = 'interrupted'
        sm%message = 'stopped by signal '//itoa(sig)//' at t = '//rtoa(s%t)//' s, step '// &
                     itoa(s%step)//'; continue with: tubempm --restart '//dir
        exit
      end if
    end do
    call system_clock(c1)
    sm%wall_seconds = seconds0 + real(c1 - c0, wp)/real(crate, wp)
    if (.not. quiet .and. tty) write(output_unit, '(a)') ''
    if (sig == 0) then
      call snap_write(snaps, s%p, s%basis, s%t, s%step, s%dt, st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      call xdmf_write(snaps, dir//'/particles.xdmf', 'particles.h5', st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
    end if
    call snap_close(snaps, st, msg)
    if (st /= 0) call fatal('output', msg, EXIT_IO)
    call history_close(hist)
    call write_summary(dir//'/summary.nml', s, sm, st, msg)
    if (st /= 0) call fatal('output', msg, EXIT_IO)
    msg = advice_end_of_run(s%bal_max, max(s%e0, s%ext_max, s%e_floor), s%energy_error)
    if (len(msg) > 0) call warn('run', msg)
    if (.not. quiet) then
      write(output_unit, '(a,i0,a,i0,a,f10.2,a)') 'done: ', s%step, ' steps, ', s%p%np, &
        ' particles, ', sm%wall_seconds, ' s'
      write(output_unit, '(a,es10.3,a,es10.3,a,es10.3)') 'runtime ratio (simulated/wall) ', &
        s%t/max(sm%wall_seconds, 1.0e-9_wp), ', particle-steps per second ', &
        real(s%p%np, wp)*real(s%step, wp)/max(sm%wall_seconds, 1.0e-9_wp), &
        ', energy error ', s%energy_error
      write(output_unit, '(a)') 'outputs in '//dir
    end if
    if (sig /= 0) then
      call write_err('ERROR [run]: '//trim(sm%message)//'; a checkpoint is in '//dir// &
                     '/checkpoint.bin and the outputs are complete up to that time')
      select case (sig)
      case (2); error stop 130
      case (15); error stop 143
      case default; error stop 5
      end select
    end if

  end subroutine run_case

  !> Keep the header and the first `rows` rows of a history file (restart).
  subroutine history_truncate(path, rows, stat, errmsg)
    character(len=*), intent(in) :: path
    integer, intent(in) :: rows
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: text, line
    character(len=512) :: msg
    integer :: u, k, i0, i1
    errmsg = ''
    text = read_text(path)
    open(newunit=u, file=path, status='replace', action='write', iostat=stat, iomsg=msg)
    if (stat /= 0) then
      errmsg = 'cannot rewrite '//path//': '//trim(msg)
      return
    end if
    i0 = 1
    do k = 0, rows
      i1 = index(text(i0:), new_line('a'))
      if (i1 == 0) exit
      line = text(i0:i0 + i1 - 2)
      write(u, '(a)', iostat=stat, iomsg=msg) line
      i0 = i0 + i1
    end do
    close(u, iostat=stat, iomsg=msg)
    if (stat /= 0) errmsg = 'cannot rewrite '//path//': '//trim(msg)
  end subroutine history_truncate

  subroutine write_err(text)
    character(len=*), intent(in) :: text
    write(error_unit, '(a)') text
    flush(error_unit)
  end subroutine write_err

  !> One progress line: in place on a terminal, a new line otherwise.
  subroutine progress(s, elapsed, tty)
    type(sim_t), intent(in) :: s
    real(wp), intent(in) :: elapsed
    logical, intent(in) :: tty
    real(wp) :: frac, eta
    character(len=160) :: line
    frac = s%t/s%t_end
    eta = elapsed*(1.0_wp - frac)/max(frac, 1.0e-12_wp)
    write(line, '(f6.2,a,es10.3,a,i0,a,f9.1,a,f9.1,a)') 100.0_wp*frac, ' %  t = ', s%t, &
      ' s  step ', s%step, '  ', real(s%step, wp)/max(elapsed, 1.0e-9_wp), &
      ' steps/s  ETA ', eta, ' s'
    if (tty) then
      write(output_unit, '(2a)', advance='no') achar(13), trim(line)
    else
      write(output_unit, '(a)') trim(line)
    end if
    flush(output_unit)
  end subroutine progress

  !> Numerical failure: save the last good state, close the outputs, write the summary, stop.
  subroutine on_failure(code, what, dir, input_text, s, good, t_good, dt_good, step_good, &
                        snaps, hist, sm)
    integer, intent(in) :: code
    character(len=*), intent(in) :: what, dir, input_text
    type(sim_t), intent(in) :: s
    type(particles_t), intent(in) :: good
    real(wp), intent(in) :: t_good, dt_good
    integer(i8), intent(in) :: step_good
    type(snapfile_t), intent(inout) :: snaps
    type(history_t), intent(inout) :: hist
    type(summary_t), intent(inout) :: sm
    character(len=:), allocatable :: crash, m2
    type(snapfile_t) :: cf
    integer :: st2
    crash = dir//'/crash_'//itoa(step_good)//'.h5'
    call snap_create(cf, crash, input_text, st2, m2)
    if (st2 == 0) call snap_write(cf, good, s%basis, t_good, step_good, dt_good, st2, m2)
    if (st2 == 0) call snap_close(cf, st2, m2)
    if (st2 /= 0) call warn('run', 'could not write the last good state: '//m2)
    call snap_close(snaps, st2, m2)
    call history_close(hist)
    sm%status = 'unstable'
    sm%message = what
    call write_summary(dir//'/summary.nml', s, sm, st2, m2)
    call fatal('run', what//new_line('a')//'the last good state (step '// &
      itoa(step_good)//', t = '//rtoa(t_good)//' s) is in '//crash// &
      '; history.csv holds every row up to the failure', code)
  end subroutine on_failure

  !> Whole text of a file ('' if unreadable).
  function read_text(path) result(text)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: text
    integer :: u, ios
    character(len=65536) :: line
    text = ''
    open(newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      text = text//trim(line)//new_line('a')
    end do
    close(u, iostat=ios)
  end function read_text
end program tubempm
