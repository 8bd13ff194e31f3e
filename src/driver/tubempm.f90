!> tubempm: material point method for thin-walled tubes under lateral compression.
! SPDX-License-Identifier: MIT
!
!   bin/tubempm CASE.nml | --check CASE.nml | --scene CASE.nml | --restart DIR | --defaults |
!   --help | --version   [--quiet]
! The driver is the only place that stops the program (exit codes of docs/output.md).
program tubempm
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, compiler_version, &
                                           compiler_options
  !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: version_string, EXIT_INPUT, EXIT_IO, path_len, BASIS_CPDI2, SCHEME_MUSL
  use mpm_errors, only: fatal, warn, halt
  use mpm_config, only: config_t, read_config, write_config, write_config_unit, default_config, &
                        scene_of
  use mpm_setup, only: setup_sim, sector_factor
  use mpm_report, only: setup_report
  use mpm_advice, only: advice_end_of_run
  use mpm_study_advice, only: study_advice
  use mpm_solver, only: sim_t, solver_step
  use mpm_particles, only: particles_t, particles_copy
  use mpm_basis, only: cpdi2_first_folded
  use mpm_output, only: history_t, history_open, history_write, history_close, write_summary, &
                        summary_t, next_output
  use mpm_images, only: images_of_walls
  use mpm_results, only: results_t, results_compute, results_write_csv, loading_walls, &
                         results_warning
  use mpm_io_hdf5, only: snapfile_t, snap_create, snap_reopen, snap_write, snap_close, xdmf_write
  use mpm_restart, only: checkpoint_write, checkpoint_read, ckpt_extra_t
  use mpm_release, only: release_t, release_observe, release_due, in_contact
  use mpm_walls, only: wall_t
  use mpm_sys, only: sys_mkdir_p, sys_dir_creatable, sys_install_signals, sys_signal_received, sys_signal_name, &
                     sys_stdout_isatty, sys_free_threads, sys_lock_dir
  use mpm_strings, only: itoa, rtoa, hms
  implicit none

  character(len=path_len) :: case_file, arg, restart_dir
  logical :: check_only, scene_only, quiet, restart, found
  integer :: i, nargs, stat
  character(len=:), allocatable :: errmsg, report, warnings, input_warnings, advice
  type(config_t) :: cfg
  type(sim_t) :: s

  !> The outputs of a run and the bookkeeping of its loop.
  type :: run_t
    character(len=:), allocatable :: dir   !! output folder
    character(len=:), allocatable :: input_text  !! the resolved input (input.nml)
    logical :: quiet = .false.             !! no progress line
    logical :: tty = .false.               !! standard output is a terminal
    type(history_t) :: hist                !! history.csv
    type(snapfile_t) :: snaps              !! particles.h5
    type(summary_t) :: sm                  !! summary.nml entries of the driver
    real(wp) :: next_snap = 0.0_wp         !! time of the next snapshot [s]
    type(particles_t) :: good              !! last good particles (crash_<step>.h5)
    real(wp) :: t_good = 0.0_wp, dt_good = 0.0_wp  !! their time and time step [s]
    integer(i8) :: step_good = 0_i8        !! their step
    integer(i8) :: c0 = 0_i8, crate = 1_i8 !! clock at the start, clock rate
    real(wp) :: seconds0 = 0.0_wp          !! wall-clock time used before a restart [s]
    integer(i8) :: step0 = 0_i8            !! step at the start of this run (a restart's) [-]
    real(wp) :: t0 = 0.0_wp                !! time at the start of this run [s]
    real(wp) :: elapsed = 0.0_wp           !! wall-clock time of this run so far [s]
    real(wp) :: last_progress = 0.0_wp     !! elapsed at the last progress line [s]
    real(wp) :: last_ckpt = 0.0_wp         !! elapsed at the last checkpoint [s]
    type(release_t) :: rel                 !! the contact seen so far (end_at_release)
    logical :: done = .false.              !! the step just taken is the last
    character(len=:), allocatable :: title !! the case's title (results.csv)
    real(wp) :: depth = 1.0_wp             !! &run depth [m]
    real(wp) :: factor = 1.0_wp            !! the sector factor (whole structure / modelled)
    real(wp) :: mass_scale = 1.0_wp        !! &solver mass_scale (the unscaled mass of &results)
  end type run_t
  character(len=*), parameter :: usage = 'tubempm [--check | --scene] [--quiet] CASE.nml | '// &
    '--restart DIR | --defaults | --help | --version'
  integer, parameter :: backup_every = 10  !! steps between copies of the last good state:
                                           !! crash_<step>.h5 is 1 to 10 steps before a failure

  ! command line
  check_only = .false.
  scene_only = .false.
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
    case ('--scene')
      scene_only = .true.
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
        call fatal('command line', 'unknown option '''//trim(arg)//'''. Usage: '//usage, &
          EXIT_INPUT)
      end if
      if (len_trim(case_file) > 0) call fatal('command line', 'more than one case file ('// &
        trim(case_file)//', '//trim(arg)//'). Usage: '//usage, EXIT_INPUT)
      case_file = arg
    end select
  end do
  if (count([check_only, scene_only, restart]) > 1) call fatal('command line', &
    '--check, --scene and --restart exclude each other (one task per call). Usage: '//usage, &
    EXIT_INPUT)
  if (restart) then
    if (len_trim(case_file) > 0) call fatal('command line', '--restart DIR takes no case '// &
      'file: the case is DIR/input.nml. Usage: tubempm --restart DIR', EXIT_INPUT)
    inquire(file=trim(restart_dir)//'/input.nml', exist=found)
    if (.not. found) call fatal('restart', trim(restart_dir)//' is not the output folder of a '// &
      'run (it has no input.nml): give the folder a run wrote into (&run output_dir, default '// &
      'out/<title>)', EXIT_IO)
    case_file = trim(restart_dir)//'/input.nml'
  end if
  if (len_trim(case_file) == 0) call fatal('command line', 'no case file given. Usage: '// &
    usage, EXIT_INPUT)
  ! Ctrl-C or a TERM from here on is a flag (not the default kill): before the outputs exist
  ! the run stops at stop_if_signalled with nothing written, after it at the end of the step
  ! with a checkpoint
  if (.not. sys_install_signals()) call warn('run', 'no signal handlers: Ctrl-C will stop the '// &
    'run without a checkpoint. Set &run checkpoint_every (docs/output.md#checkpoints-and-restart)')

  ! input, set-up, report
  call read_config(case_file, cfg, stat, errmsg, input_warnings)
  if (stat /= 0) call fatal('input', errmsg, stat)
  if (scene_only) then                   ! the kind of scene summary.nml will name, for plots/
    if (len_trim(scene_of(cfg)) == 0) then
      write(output_unit, '(a)') 'generic'
    else
      write(output_unit, '(a)') trim(scene_of(cfg))
    end if
    stop
  end if
  ! a completed run has nothing to continue (its input read and valid): say so, touch nothing
  if (restart) call stop_if_complete(trim(restart_dir))
  if (restart) cfg%run%output_dir = restart_dir
  if (len(input_warnings) > 0) call print_warnings(input_warnings)
  call setup_sim(cfg, s, stat, errmsg)
  if (stat /= 0) call fatal('input', errmsg, stat)
  call stop_if_signalled('the set-up')
  call choose_threads(cfg%run%threads, check_only .or. s%p%np < s%prm%parallel_min, quiet)
  call setup_report(cfg, s, report, warnings)
  if (check_only .or. .not. quiet) then
    write(output_unit, '(a)') report
    flush(output_unit)
  end if
  if (len(warnings) > 0) call print_warnings(warnings)
  if (check_only) then
    call study_advice(cfg, s%g%h, s%prm%cfl, s%walls(1:s%nwall), advice)
    if (len(advice) > 0) write(output_unit, '(a)') advice
    call warn_if_not_creatable(trim(cfg%run%output_dir))
    write(output_unit, '(a)') 'input ok: '//trim(case_file)
    stop
  end if
  call run_case(cfg, s, quiet, restart)

contains

  !> --check: a warning when the output folder could not be made here (the run would stop with
  !! exit 3); a warning, not an error, since a batch job may run where the folder can be made.
  subroutine warn_if_not_creatable(dir)
    character(len=*), intent(in) :: dir    !! &run output_dir
    integer :: st
    character(len=:), allocatable :: msg
    call sys_dir_creatable(dir, st, msg)
    if (st /= 0) call warn('check', 'output_dir '''//dir//''' cannot be written here ('//msg// &
      '). Set &run output_dir to a writable folder (docs/input.md#run)')
  end subroutine warn_if_not_creatable

  !> A signal received before the outputs are opened: stop (exit 128 + signal, as shells
  !! report it) with nothing written.
  subroutine stop_if_signalled(stage)
    character(len=*), intent(in) :: stage  !! what was being done
    integer :: sig
    sig = sys_signal_received()
    if (sig /= 0) call halt('stopped by '//sys_signal_name(sig)//' during '//stage// &
      ': nothing written, nothing lost', 128 + sig)
  end subroutine stop_if_signalled

  !> The threads of the run: `&run threads` when given; with 0 and no OMP_NUM_THREADS, the
  !! runtime default without the cores other work keeps busy (sys_free_threads), said when it
  !! leaves any out.
  subroutine choose_threads(threads, serial, quiet)
    integer, intent(in) :: threads         !! &run threads (0 = runtime default)
    logical, intent(in) :: serial          !! no parallel loops follow (--check, small scenes)
    logical, intent(in) :: quiet           !! no progress lines
    integer :: nmax, n, ios, free
    character(len=:), allocatable :: why
    if (threads > 0) then
      !$ call omp_set_num_threads(threads)
      return
    end if
    call get_environment_variable('OMP_NUM_THREADS', length=n, status=ios)
    if (ios == 0 .and. n > 0) return       ! the count the user gave the runtime
    if (serial) return
    nmax = 1
    !$ nmax = omp_get_max_threads()
    call sys_free_threads(nmax, free, why)
    if (free == nmax) return
    !$ call omp_set_num_threads(free)
    if (.not. quiet) write(output_unit, '(a)') 'threads: '//itoa(free)//' of '//itoa(nmax)// &
      ' ('//why//'; &run threads or OMP_NUM_THREADS sets the count)'
  end subroutine choose_threads

  subroutine print_help()
    write(output_unit, '(a)') 'tubempm '//version_string// &
      ': material point method (CPDI) for thin-walled tubes under lateral compression'
    write(output_unit, '(a)') ''
    write(output_unit, '(a)') 'usage:'
    write(output_unit, '(a)') '  tubempm CASE.nml             run the case (outputs in &run output_dir)'
    write(output_unit, '(a)') '  tubempm --check CASE.nml     validate; print the derived set-up and exit'
    write(output_unit, '(a)') '  tubempm --scene CASE.nml     print the kind of scene (crush, wave, '// &
      'impact, generic)'
    write(output_unit, '(a)') '                               that summary.nml will name; '// &
      'nothing is run'
    write(output_unit, '(a)') '  tubempm --restart DIR        continue the run in DIR from its last checkpoint'
    write(output_unit, '(a)') '  tubempm --defaults           print every namelist group with its defaults'
    write(output_unit, '(a)') '  tubempm --help | --version'
    write(output_unit, '(a)') '  --quiet                      no set-up report, progress or end-of-run lines '// &
      '(warnings and errors still printed)'
    write(output_unit, '(a)') ''
    write(output_unit, '(a)') 'exit status: 0 ok, 1 internal error, 2 bad input, 3 I/O failure,'
    write(output_unit, '(a)') '             4 numerical failure, 130 / 143 stopped by SIGINT / SIGTERM'
    write(output_unit, '(a)') '             (128 + the signal, as shells report it; a checkpoint is written)'
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

  !> The run: open the outputs (or continue them from the checkpoint), loop over the steps,
  !! close the outputs. Every exit but success goes through fatal.
  subroutine run_case(cfg, s, quiet, restart)
    type(config_t), intent(inout) :: cfg
    type(sim_t), intent(inout) :: s
    logical, intent(in) :: quiet, restart
    type(run_t) :: r
    integer :: st, sig
    character(len=:), allocatable :: msg
    r%quiet = quiet
    r%title = trim(cfg%run%title)
    r%depth = cfg%run%depth
    r%factor = sector_factor(cfg)
    r%mass_scale = cfg%solver%mass_scale
    ! 1. outputs: new, or continued from the checkpoint (a signal from here on stops the loop
    ! after its first step, with a checkpoint)
    call stop_if_signalled('the report')
    call open_outputs(cfg, s, restart, r)
    r%sm%scene = scene_of(cfg)             ! the scene rule --check advises by
    call keep_good_state(s, r)
    call system_clock(r%c0, r%crate)
    r%step0 = s%step                       ! a restart's speed and ETA count from here
    r%t0 = s%t
    ! 2. the time loop
    sig = 0
    r%done = s%t >= s%prm%t_end
    do while (.not. r%done)
      call solver_step(s, st, msg)
      if (st /= 0) call on_failure(st, msg, s, r)
      r%done = s%t >= s%prm%t_end              ! (at t_end the contact is no longer watched)
      if (.not. r%done) r%done = released(cfg, s, r)
      call write_outputs(cfg, s, r)
      if (mod(s%step, int(backup_every, i8)) == 0_i8) call keep_good_state(s, r)
      call show_progress(s, r)
      sig = sys_signal_received()
      if (sig /= 0 .or. (cfg%run%checkpoint_every > 0.0_wp .and. &
                         r%elapsed - r%last_ckpt >= cfg%run%checkpoint_every)) then
        call write_checkpoint(s, r)
      end if
      if (sig /= 0) then
        r%sm%status = 'interrupted'
        r%sm%message = 'stopped by '//sys_signal_name(sig)//' at t = '//rtoa(s%t)//' s, step '// &
                       itoa(s%step)
        exit
      end if
    end do
    if (r%done .and. s%t < s%prm%t_end) r%sm%message = 'ended at release: contact from t = '// &
      rtoa(r%rel%t_first)//' to '//rtoa(r%rel%t_last)//' s, none since (&run end_at_release)'
    ! 3. close the outputs, summary, end-of-run report
    call close_outputs(s, r, final_snapshot=sig == 0)
    if (sig /= 0) call halt('stopped by '//sys_signal_name(sig)//': checkpoint saved, '// &
      'continue with tubempm --restart '//r%dir, 128 + sig)   ! exit status as shells report it
  end subroutine run_case

  !> Open the outputs of a new run (folder, input.nml, history, particles.h5 with the first
  !! snapshot), or reopen them from the checkpoint of a run to continue (restart).
  subroutine open_outputs(cfg, s, restart, r)
    type(config_t), intent(in) :: cfg
    type(sim_t), intent(inout) :: s
    logical, intent(in) :: restart
    type(run_t), intent(inout) :: r
    type(ckpt_extra_t) :: ex
    integer, allocatable :: probes(:)
    character(len=:), allocatable :: msg
    integer :: st
    r%dir = trim(cfg%run%output_dir)
    r%seconds0 = 0.0_wp
    r%tty = sys_stdout_isatty()
    r%sm%threads = 1
    !$ r%sm%threads = omp_get_max_threads()
    if (s%p%np < s%prm%parallel_min) r%sm%threads = 1   ! small scenes: serial loops
    probes = probe_particles(cfg, s)         ! nearest particles at t = 0 (before a restart)
    if (restart) then
      call lock_folder(r%dir)
      call stop_if_complete(r%dir)          ! (again: another restart may have ended it)
      r%input_text = read_text(r%dir//'/input.nml')
      call checkpoint_read(r%dir, r%input_text, s, ex, st, msg)
      if (st == 2) call fatal('restart', msg, EXIT_INPUT)
      if (st /= 0) call fatal('restart', msg, EXIT_IO)
      r%seconds0 = ex%wall_seconds
      call history_truncate(r%dir//'/history.csv', ex%history_rows, st, msg)
      if (st /= 0) call fatal('restart', msg, EXIT_IO)
      call history_open(r%hist, r%dir//'/history.csv', s, cfg%run%history_every, &
                        cfg%run%depth, sector_factor(cfg), probes, st, msg, append=.true.)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      r%hist%rows = ex%history_rows
      r%hist%next_time = ex%history_next
      r%hist%last_time = ex%history_last
      call snap_reopen(r%snaps, r%dir//'/particles.h5', ex%snap_times, ex%snap_np, ex%snap_nc, &
                       st, msg)
      if (st /= 0) call fatal('restart', msg, EXIT_IO)
      r%snaps%images = images_of_walls(s%walls, cfg%run%mirror_images)
      r%next_snap = ex%snapshot_next
      r%rel = release_t(ex%contact_first, ex%contact_last)
      if (.not. r%quiet) write(output_unit, '(a)') 'restarting from the checkpoint at t = '// &
        rtoa(s%t)//' s, step '//itoa(s%step)
    else
      call sys_mkdir_p(r%dir, st, msg)
      if (st /= 0) call fatal('output', 'cannot create the output folder '//r%dir//': '//msg// &
        '. Choose a writable &run output_dir', EXIT_IO)
      call lock_folder(r%dir)
      call replace_finished_run(r%dir)
      call write_config(cfg, r%dir//'/input.nml', st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      r%input_text = read_text(r%dir//'/input.nml')
      call history_open(r%hist, r%dir//'/history.csv', s, cfg%run%history_every, &
                        cfg%run%depth, sector_factor(cfg), probes, st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      call snap_create(r%snaps, r%dir//'/particles.h5', r%input_text, st, msg)
      if (st /= 0) call fatal('output', msg//' ('//r%dir//'/particles.h5)', EXIT_IO)
      r%snaps%images = images_of_walls(s%walls, cfg%run%mirror_images)
      call history_write(r%hist, s, .true., st, msg)
      if (st /= 0) call fatal('output', msg, EXIT_IO)
      call write_snapshot(s, r)
      r%next_snap = cfg%run%snapshot_every
    end if
  end subroutine open_outputs

  !> Hold the output folder for this run: a second run writing into it would corrupt both
  !! (a run started while another writes there is refused, before it writes anything).
  subroutine lock_folder(dir)
    character(len=*), intent(in) :: dir
    integer :: st
    character(len=:), allocatable :: msg
    call sys_lock_dir(dir, st, msg)
    if (st == -1) call fatal('output', 'another tubempm run is writing into '//dir// &
      ' (it holds the folder''s lock): wait until it ends, or choose another &run output_dir', &
      EXIT_IO)
    if (st == -2) call warn('output', 'no folder locks on the file system of '//dir//': a '// &
      'second run into it would not be noticed. Start one run per folder (docs/output.md)')
    if (st > 0) call fatal('output', 'cannot lock the output folder '//msg, EXIT_IO)
  end subroutine lock_folder

  !> A new run in a folder that holds an earlier run: refused when that run was stopped before
  !! its end and can be continued (a checkpoint, and no summary.nml saying it completed or
  !! failed): its work would be lost. Otherwise its checkpoint and summary are removed, and a
  !! summary.nml with status = 'running' stands for this run until its end, so that a run killed
  !! outright (SIGKILL, a node lost) is not taken for a finished one.
  subroutine replace_finished_run(dir)
    character(len=*), intent(in) :: dir
    character(len=:), allocatable :: status, why
    logical :: ckpt
    integer :: u, ios
    inquire(file=dir//'/checkpoint.bin', exist=ckpt)
    status = summary_status(dir)
    if (ckpt .and. status /= 'completed' .and. status /= 'unstable') then
      select case (status)
      case ('none')
        why = 'no summary.nml'
      case ('interrupted')
        why = "summary.nml: status = 'interrupted'"
      case ('running')
        why = "summary.nml: status = 'running': it was killed"
      case default
        why = 'a summary.nml without an end status'
      end select
      call fatal('output', dir//' holds a run that stopped before its end and can be '// &
        'continued ('//why//', and a checkpoint.bin): continue it with tubempm --restart '// &
        dir//', or remove the folder (or choose another &run output_dir) to start afresh', &
        EXIT_IO)
    end if
    open(newunit=u, file=dir//'/checkpoint.bin', status='old', iostat=ios)
    if (ios == 0) close(u, status='delete', iostat=ios)
    open(newunit=u, file=dir//'/summary.nml', status='replace', action='write', iostat=ios)
    if (ios == 0) write(u, '(a)', iostat=ios) '&summary', "  status = 'running'", '/'
    if (ios == 0) close(u, iostat=ios)
  end subroutine replace_finished_run

  !> The status in dir/summary.nml ('completed', 'running', ...; 'none' without the file, ''
  !! when it names none).
  function summary_status(dir) result(status)
    character(len=*), intent(in) :: dir
    character(len=:), allocatable :: status, text
    integer :: p, q
    text = read_text(dir//'/summary.nml')
    status = 'none'
    if (len(text) == 0) return
    status = ''
    p = index(text, "status = '")
    if (p == 0) return
    p = p + len("status = '")
    q = index(text(p:), "'")
    if (q > 1) status = text(p:p+q-2)
  end function summary_status

  !> A completed run has nothing to continue: say so and stop, touching nothing.
  subroutine stop_if_complete(dir)
    character(len=*), intent(in) :: dir
    if (summary_status(dir) /= 'completed') return
    write(output_unit, '(a)') 'the run in '//dir//' is complete (summary.nml: '// &
      'status = ''completed''): nothing to restart; its outputs are left as they are'
    stop
  end subroutine stop_if_complete

  !> With `&run end_at_release`: record whether the step just taken had a contact force, and
  !! whether the contact is over (mpm_release).
  logical function released(cfg, s, r)
    type(config_t), intent(in) :: cfg
    type(sim_t), intent(in) :: s
    type(run_t), intent(inout) :: r
    type(wall_t) :: none(0)
    real(wp) :: no_pairs(3, 0)
    logical :: on
    released = .false.
    if (.not. cfg%run%end_at_release) return
    on = .false.
    if (s%nwall > 0) on = in_contact(s%walls(1:s%nwall), no_pairs, s%t)
    if (s%prm%npair > 0) on = on .or. in_contact(none, s%pair_force, s%t)
    call release_observe(r%rel, s%t, on)
    released = release_due(r%rel, s%t, s%dt)
  end function released

  !> After a step: the history row when due, the snapshot when due.
  subroutine write_outputs(cfg, s, r)
    type(config_t), intent(in) :: cfg
    type(sim_t), intent(inout) :: s
    type(run_t), intent(inout) :: r
    character(len=:), allocatable :: msg
    integer :: st
    call history_write(r%hist, s, r%done, st, msg)
    if (st /= 0) call fatal('output', msg, EXIT_IO)
    if (cfg%run%snapshot_every > 0.0_wp .and. s%t >= r%next_snap*(1.0_wp - 1.0e-12_wp) &
        .and. .not. r%done) then
      call write_snapshot(s, r)
      r%next_snap = next_output(r%next_snap, cfg%run%snapshot_every, s%t)
    end if
  end subroutine write_outputs

  !> One snapshot into particles.h5, and the XDMF index rewritten.
  subroutine write_snapshot(s, r)
    type(sim_t), intent(in) :: s
    type(run_t), intent(inout) :: r
    character(len=:), allocatable :: msg
    integer :: st
    call snap_write(r%snaps, s%p, s%prm%basis, s%t, s%step, s%dt, st, msg)
    if (st /= 0) call fatal('output', msg, EXIT_IO)
    call xdmf_write(r%snaps, r%dir//'/particles.xdmf', 'particles.h5', st, msg)
    if (st /= 0) call fatal('output', msg, EXIT_IO)
  end subroutine write_snapshot

  !> Keep a copy of the particles as the last good state (for crash_<step>.h5). A CPDI2
  !! domain folded by the step just taken is caught only by the next step's basis, so a state
  !! with a folded domain is not kept (the copy before it stays the last good state).
  subroutine keep_good_state(s, r)
    type(sim_t), intent(in) :: s
    type(run_t), intent(inout) :: r
    if (s%prm%basis == BASIS_CPDI2 .and. allocated(r%good%x)) then
      if (cpdi2_first_folded(s%p%np, s%p%nc, s%p%corner, s%p%xc) > 0) return
    end if
    call particles_copy(r%good, s%p)
    r%t_good = s%t
    r%dt_good = s%dt
    r%step_good = s%step
  end subroutine keep_good_state

  !> The progress line when due (in place on a terminal, every 10 s otherwise); the elapsed
  !! wall-clock time.
  subroutine show_progress(s, r)
    type(sim_t), intent(in) :: s
    type(run_t), intent(inout) :: r
    integer(i8) :: c1
    call system_clock(c1)
    r%elapsed = real(c1 - r%c0, wp)/real(r%crate, wp)
    if (.not. r%quiet .and. (r%elapsed - r%last_progress > merge(0.5_wp, 10.0_wp, r%tty))) then
      call progress(s, r, r%tty)
      r%last_progress = r%elapsed
    end if
  end subroutine show_progress

  !> Checkpoint with the output positions; an I/O failure here stops the run (exit 3).
  subroutine write_checkpoint(s, r)
    type(sim_t), intent(in) :: s
    type(run_t), intent(inout) :: r
    type(ckpt_extra_t) :: ex
    character(len=:), allocatable :: msg
    integer :: st
    ex%history_rows = r%hist%rows
    ex%history_next = r%hist%next_time
    ex%history_last = r%hist%last_time
    ex%snapshot_next = r%next_snap
    ex%snap_times = r%snaps%times
    ex%snap_np = r%snaps%nps
    ex%snap_nc = r%snaps%ncs
    ex%wall_seconds = r%seconds0 + r%elapsed
    ex%contact_first = r%rel%t_first
    ex%contact_last = r%rel%t_last
    call checkpoint_write(r%dir, r%input_text, s, ex, st, msg)
    if (st /= 0) call fatal('checkpoint', msg, EXIT_IO)
    r%last_ckpt = r%elapsed
  end subroutine write_checkpoint

  !> Close the outputs: the last snapshot (unless interrupted), particles.h5, history.csv,
  !! summary.nml; the end-of-run warning and report.
  subroutine close_outputs(s, r, final_snapshot)
    type(sim_t), intent(in) :: s
    type(run_t), intent(inout) :: r
    logical, intent(in) :: final_snapshot
    character(len=:), allocatable :: msg
    type(results_t) :: res
    integer :: st
    integer(i8) :: c1
    call system_clock(c1)
    r%sm%wall_seconds = r%seconds0 + real(c1 - r%c0, wp)/real(r%crate, wp)
    if (.not. r%quiet .and. r%tty) write(output_unit, '(a)') ''
    if (final_snapshot) call write_snapshot(s, r)
    call snap_close(r%snaps, st, msg)
    if (st /= 0) call fatal('output', msg, EXIT_IO)
    call history_close(r%hist)
    call results_of_run(s, r, res)
    call write_summary(r%dir//'/summary.nml', s, r%sm, st, msg, res)
    if (st /= 0) call fatal('output', msg, EXIT_IO)
    if (res%valid) call results_write_csv(r%dir//'/results.csv', r%title, res, st, msg)
    if (st /= 0) call fatal('output', msg, EXIT_IO)
    msg = results_warning(res)
    if (len(msg) > 0) call warn('results', msg)
    msg = advice_end_of_run(s%bal_max, max(s%e0, s%ext_max, s%prm%e_floor), s%energy_error, &
      s%prm%scheme == SCHEME_MUSL .and. s%prm%flip == 1.0_wp, s%prm%nf > 1)
    if (len(msg) > 0) call warn('run', msg)
    if (.not. r%quiet) then
      write(output_unit, '(a,i0,a,i0,a,f10.2,a)') trim(merge('stopped: ', 'done:    ', &
        r%sm%status == 'interrupted'))//' ', s%step, ' steps, ', s%p%np, &
        ' particles, ', r%sm%wall_seconds, ' s'
      write(output_unit, '(a,es10.3,a,es10.3,a,es10.3)') 'runtime ratio (simulated/wall) ', &
        s%t/max(r%sm%wall_seconds, 1.0e-9_wp), ', particle-steps per second ', &
        real(s%p%np, wp)*real(s%step, wp)/max(r%sm%wall_seconds, 1.0e-9_wp), &
        ', energy error ', s%energy_error
      write(output_unit, '(a)') 'outputs in '//r%dir
    end if
  end subroutine close_outputs

  !> The run's &results (mpm_results) from its history.csv, its loading walls' work, the stored
  !! elastic energy and the bodies' unscaled mass, for depth and the whole structure. A history
  !! that cannot be read back leaves the results out, with a warning.
  subroutine results_of_run(s, r, res)
    type(sim_t), intent(in) :: s
    type(run_t), intent(in) :: r
    type(results_t), intent(out) :: res
    character(len=:), allocatable :: msg
    logical :: loading(s%nwall)
    real(wp) :: scale
    integer :: st
    scale = r%depth*r%factor
    loading = loading_walls(s%walls(1:s%nwall))
    call results_compute(r%dir//'/history.csv', s%walls(1:s%nwall), &
      sum(s%walls(1:s%nwall)%work, mask=loading)*scale, (s%e_strain + s%e_contact)*scale, &
      sum(s%p%mass)/r%mass_scale*scale, s%prm%nbody, res, st, msg)
    if (st /= 0) call warn('output', 'no &results: '//msg)
  end subroutine results_of_run

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

  !> One progress line: in place on a terminal, a new line otherwise.
  !! The speed and the ETA count from this run's start (a restart's checkpoint), not from t = 0.
  subroutine progress(s, r, tty)
    type(sim_t), intent(in) :: s
    type(run_t), intent(in) :: r           !! this run's start and elapsed time
    logical, intent(in) :: tty
    real(wp) :: frac, eta
    character(len=160) :: line
    frac = s%t/s%prm%t_end
    eta = r%elapsed*(s%prm%t_end - s%t)/max(s%t - r%t0, 1.0e-12_wp*s%prm%t_end)
    write(line, '(f6.2,a,es10.3,a,i0,a,f9.1,2a)') 100.0_wp*frac, ' %  t = ', s%t, &
      ' s  step ', s%step, '  ', real(s%step - r%step0, wp)/max(r%elapsed, 1.0e-9_wp), &
      ' steps/s  ETA ', hms(eta)
    if (tty) then
      write(output_unit, '(2a)', advance='no') achar(13), trim(line)
    else
      write(output_unit, '(a)') trim(line)
    end if
    flush(output_unit)
  end subroutine progress

  !> Numerical failure: save the last good state, close the outputs, write the summary, stop.
  subroutine on_failure(code, what, s, r)
    integer, intent(in) :: code
    character(len=*), intent(in) :: what
    type(sim_t), intent(in) :: s
    type(run_t), intent(inout) :: r
    character(len=:), allocatable :: crash, m2
    type(snapfile_t) :: cf
    type(results_t) :: res
    integer :: st2
    integer(i8) :: c1
    call system_clock(c1)
    r%sm%wall_seconds = r%seconds0 + real(c1 - r%c0, wp)/real(r%crate, wp)
    crash = r%dir//'/crash_'//itoa(r%step_good)//'.h5'
    call snap_create(cf, crash, r%input_text, st2, m2)
    cf%images = r%snaps%images
    if (st2 == 0) call snap_write(cf, r%good, s%prm%basis, r%t_good, r%step_good, r%dt_good, &
                                  st2, m2)
    if (st2 == 0) call snap_close(cf, st2, m2)
    if (st2 /= 0) call warn('run', 'could not write the last good state: '//m2)
    call snap_close(r%snaps, st2, m2)
    call history_close(r%hist)
    r%sm%status = 'unstable'
    r%sm%message = what
    call results_of_run(s, r, res)
    call write_summary(r%dir//'/summary.nml', s, r%sm, st2, m2, res)
    if (st2 == 0 .and. res%valid) call results_write_csv(r%dir//'/results.csv', r%title, res, st2, m2)
    call fatal('run', what//new_line('a')//'the last good state (step '// &
      itoa(r%step_good)//', t = '//rtoa(r%t_good)//' s) is in '//crash// &
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
