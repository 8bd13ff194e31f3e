!> Benchmark driver of `make bench` (release build; never part of `make test`): times one fixed
!! ring scene with one basis and thread count, and prints one CSV row (tools/bench.py runs the
!! series, makes the table and the plot).
! SPDX-License-Identifier: MIT
!
! usage: bench --header
!        bench SCENE BASIS N_THICK THREADS STEPS REPS [DETERMINISTIC [SCHEME]]
!   SCENE  crush  steel ring (Sinaie et al. 2018 specimen), quarter sector, top platen 5 m/s
!          impact aluminium ring, half sector, touching a rigid target at 30 m/s
!   BASIS  linear | ugimp | cpdi1 | cpdi2;  N_THICK particles through the wall (even), the cell
!          is h = t / (N_THICK/2), i.e. 2 x 2 particles per cell; J2 plasticity, plane strain
!   THREADS 1, 2, ...; 0: as a run with &run threads = 0, the cores no other work keeps busy
!          (the row gives the count chosen)
!   STEPS  time steps per repetition; REPS repetitions (after 3 untimed warm-up steps)
!   DETERMINISTIC 0 | 1 (default 0); SCHEME usl | usf | musl (default musl)
!        bench --case-header
!        bench case FILE THREADS STEPS REPS [SKIP]
!   FILE   a case file (namelist), run as read (its outputs are not written); SKIP untimed steps
!          first (default 3); the row (tools/bench.py --cost): particles, nodes, velocity
!          fields, foam particles, particle-steps per second (best and median of REPS, and over
!          all of them), the mean contact nodes, particles touching them, pair entries and those
!          between two bodies per step, the counts of --check's cost model at t = 0 (mpm_cost:
!          pair entries between bodies, surface nodes facing, entries within a body), ns per
!          particle-step of each phase, and per pair of bodies with a law its entries and
!          facing nodes at t = 0 ('t:s;t:s')
! Row: scene, basis, scheme, deterministic, threads, particles, nodes, block width, steps, reps,
! particle-steps per second (median, min, max; median per CPU second of all threads: robust to
! other load, but it counts the time threads spin at barriers), runtime ratio (simulated /
! wall time, median), yielded fraction, ns per particle-step of each phase (mpm_timers),
! modelled memory [bytes], peak resident memory VmHWM [bytes].
program bench
  !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: basis_names, scheme_names, SCHEME_MUSL, PLANE_STRAIN, MODEL_J2, &
                           SECTOR_HALF, SECTOR_QUARTER
  use mpm_config, only: config_t, config_resolve, read_config
  use mpm_scene_builder, only: scene_new, scene_add_material, scene_add_ring, scene_add_wall
  use mpm_setup, only: setup_sim
  use mpm_solver, only: sim_t, solver_step, solver_memory_bytes
  use mpm_timers, only: clock_seconds, n_phases, phase_names
  use mpm_sys, only: sys_free_threads
  use mpm_cost, only: cost_counts_t, cost_case_counts
  implicit none
  integer, parameter :: warm_steps = 3
  character(len=512) :: arg(8)
  character(len=:), allocatable :: errmsg, why
  type(config_t) :: cfg
  type(sim_t) :: s
  integer :: nargs, k, basis, scheme, n_thick, threads, steps, reps, rep, stat, det, nmax
  real(wp) :: t0, t1, t_sim0, cpu0, cpu1
  real(wp), allocatable :: rate(:), ratio(:), cpu_rate(:)
  real(wp) :: phase(n_phases)
  character(len=2048) :: line

  nargs = command_argument_count()
  arg(1) = ''
  if (nargs == 1) call get_command_argument(1, arg(1))
  if (arg(1) == '--header') then
    line = 'scene,basis,scheme,deterministic,threads,particles,nodes,nb,steps,reps,' // &
           'mps_median,mps_min,mps_max,mps_cpu,runtime_ratio,yielded'
    do k = 1, n_phases
      line = trim(line)//',ns_'//trim(phase_names(k))
    end do
    write(output_unit, '(a)') trim(line)//',memory_model_bytes,vmhwm_bytes'
  else if (arg(1) == '--case-header') then
    line = 'case,basis,threads,particles,nodes,nf,foam_particles,steps,reps,t_start,t_end,' // &
           'mps_best,mps_median,mps_all,contact_nodes,contact_particles,pair_entries,' // &
           'body_entries,touching0,facing0,self0'
    do k = 1, n_phases
      line = trim(line)//',ns_'//trim(phase_names(k))
    end do
    write(output_unit, '(a)') trim(line)//',pairs0'
  else
    call get_command_argument(1, arg(1))
    if (arg(1) == 'case') then
      call run_case()
    else
      call run_scene()
    end if
  end if

contains

  !> Parse the arguments, set the scene up, time it and print its row.
  subroutine run_scene()
    if (nargs < 6) then
      write(error_unit, '(a)') 'usage: bench --header | bench SCENE BASIS N_THICK THREADS '// &
        'STEPS REPS [DETERMINISTIC [SCHEME]]'
      error stop 2
    end if
    do k = 1, min(nargs, 8)
      call get_command_argument(k, arg(k))
    end do
    basis = findloc(basis_names, trim(arg(2)), dim=1)
    read(arg(3), *) n_thick
    read(arg(4), *) threads
    read(arg(5), *) steps
    read(arg(6), *) reps
    det = 0
    if (nargs >= 7) read(arg(7), *) det
    scheme = SCHEME_MUSL
    if (nargs >= 8) scheme = findloc(scheme_names, trim(arg(8)), dim=1)
    if (basis == 0 .or. scheme == 0 .or. n_thick < 2 .or. threads < 0 .or. steps < 1 &
        .or. reps < 1) then
      write(error_unit, '(a)') 'bench: bad arguments'
      error stop 2
    end if
    if (threads == 0) then                 ! as tubempm with &run threads = 0
      nmax = 1
      !$ nmax = omp_get_max_threads()
      call sys_free_threads(nmax, threads, why)
    end if
    !$ call omp_set_num_threads(threads)

    select case (trim(arg(1)))
    case ('crush')
      cfg = scene_case(basis, scheme, 210.0e9_wp, 0.3_wp, 7800.0_wp, 310.0e6_wp, 10.0e6_wp, &
                       23.95e-3_wp, 25.43e-3_wp, n_thick, SECTOR_QUARTER, [0.0_wp, 0.0_wp])
      cfg%bodies(1)%center = [0.0_wp, 25.43e-3_wp]
      cfg%walls(1)%point = [0.0_wp, 2.0_wp*25.43e-3_wp]      ! top platen on the ring at t = 0
      cfg%walls(1)%normal = [0.0_wp, -1.0_wp]
      cfg%walls(1)%velocity = [0.0_wp, -5.0_wp]
    case ('impact')
      cfg = scene_case(basis, scheme, 70.0e9_wp, 0.33_wp, 2700.0_wp, 150.0e6_wp, 200.0e6_wp, &
                       24.0e-3_wp, 26.0e-3_wp, n_thick, SECTOR_HALF, [0.0_wp, -30.0_wp])
      cfg%bodies(1)%center = [0.0_wp, 26.0e-3_wp]           ! touching the target at t = 0
      cfg%walls(1)%point = [0.0_wp, 0.0_wp]
      cfg%walls(1)%normal = [0.0_wp, 1.0_wp]
    case default
      write(error_unit, '(a)') 'bench: SCENE is crush or impact'
      error stop 2
    end select
    cfg%solver%deterministic = det /= 0
    call config_resolve(cfg, stat, errmsg)
    call stop_unless_ok('bad case')
    call setup_sim(cfg, s, stat, errmsg)
    call stop_unless_ok('setup failed')

    do k = 1, warm_steps
      call step_or_stop()
    end do
    allocate(rate(reps), ratio(reps), cpu_rate(reps))
    s%diag%phase_time = 0.0_wp
    do rep = 1, reps
      t_sim0 = s%t
      t0 = clock_seconds()
      call cpu_time(cpu0)
      do k = 1, steps
        call step_or_stop()
      end do
      call cpu_time(cpu1)
      t1 = clock_seconds()
      rate(rep) = real(s%p%np, wp)*real(steps, wp)/(t1 - t0)
      cpu_rate(rep) = real(s%p%np, wp)*real(steps, wp)/(cpu1 - cpu0)
      ratio(rep) = (s%t - t_sim0)/(t1 - t0)
    end do
    phase = s%diag%phase_time/(real(s%p%np, wp)*real(steps, wp)*real(reps, wp))*1.0e9_wp
    write(line, '(a,",",a,",",a,",",i0,",",i0,",",i0,",",i0,",",i0,",",i0,",",i0,' // &
          '5(",",es11.4),",",f7.4)') trim(arg(1)), trim(basis_names(basis)), &
          trim(scheme_names(scheme)), det, threads, s%p%np, s%g%nn, s%wk%nb, steps, reps, &
          median(rate), minval(rate), maxval(rate), median(cpu_rate), median(ratio), &
          real(count(s%p%eqps > 0.0_wp), wp)/real(s%p%np, wp)
    do k = 1, n_phases
      write(line, '(a,",",f9.2)') trim(line), phase(k)
    end do
    write(output_unit, '(a,",",i0,",",i0)') trim(line), solver_memory_bytes(s), peak_rss()
  end subroutine run_scene

  !> A case file's scene: SKIP untimed steps, then REPS times STEPS timed steps on THREADS
  !! threads; one row (--case-header) with the contact work counted per timed step.
  subroutine run_case()
    integer :: skip, nfoam
    real(wp) :: t_start, ncn, npl, npn, nbe, tsum
    integer :: taken, total, done
    type(cost_counts_t) :: c0
    if (nargs < 5) then
      write(error_unit, '(a)') 'usage: bench case FILE THREADS STEPS REPS [SKIP]'
      error stop 2
    end if
    do k = 2, min(nargs, 6)
      call get_command_argument(k, arg(k))
    end do
    read(arg(3), *) threads
    read(arg(4), *) steps
    read(arg(5), *) reps
    skip = warm_steps
    if (nargs >= 6) read(arg(6), *) skip
    if (threads < 1 .or. steps < 1 .or. reps < 1 .or. skip < 0) then
      write(error_unit, '(a)') 'bench: bad arguments'
      error stop 2
    end if
    !$ call omp_set_num_threads(threads)
    call read_config(trim(arg(2)), cfg, stat, errmsg)
    call stop_unless_ok('bad case')
    call setup_sim(cfg, s, stat, errmsg)
    call stop_unless_ok('setup failed')
    c0 = cost_case_counts(s)             ! what --check counts at t = 0
    nfoam = nint(c0%foam)
    do k = 1, skip
      call step_or_stop()
    end do
    t_start = s%t
    allocate(rate(reps))
    s%diag%phase_time = 0.0_wp
    ncn = 0.0_wp
    npl = 0.0_wp
    npn = 0.0_wp
    nbe = 0.0_wp
    tsum = 0.0_wp
    total = 0
    done = 0
    do rep = 1, reps
      t0 = clock_seconds()
      taken = 0
      do k = 1, steps
        if (s%t >= s%prm%t_end) exit      ! the case's end: a step there is refused
        call step_or_stop()
        taken = taken + 1
        ncn = ncn + real(s%wk%fc%ncn, wp)
        npl = npl + real(s%wk%fc%nplist, wp)
        npn = npn + real(s%wk%fc%npn, wp)
        nbe = nbe + real(body_entries(), wp)
      end do
      t1 = clock_seconds()
      if (taken == 0) exit
      done = rep
      total = total + taken
      tsum = tsum + (t1 - t0)
      rate(rep) = real(s%p%np, wp)*real(taken, wp)/(t1 - t0)
      ! each repetition on standard error: a run's throughput along its time
      write(error_unit, '(a,i0,2(a,es11.4))') 'rep ', rep, ' t ', s%t, ' mps ', rate(rep)
      flush(error_unit)
    end do
    if (done == 0) then
      write(error_unit, '(a)') 'bench: no step before the case''s t_end'
      error stop 2
    end if
    phase = s%diag%phase_time/(real(s%p%np, wp)*real(total, wp))*1.0e9_wp
    ! (the wall time of all the timed steps: a run's throughput over its whole time)
    write(line, '(a,",",a,",",i0,",",i0,",",i0,",",i0,",",i0,",",i0,",",i0,' // &
          '5(",",es11.4),7(",",f10.2))') trim(arg(2)), trim(basis_names(s%prm%basis)), &
          threads, s%p%np, s%g%nn, s%prm%nf, nfoam, total, done, t_start, s%t, &
          maxval(rate(1:done)), median(rate(1:done)), &
          real(s%p%np, wp)*real(total, wp)/tsum, &
          [ncn, npl, npn, nbe]/real(total, wp), c0%touching, c0%facing, c0%self
    do k = 1, n_phases
      write(line, '(a,",",f9.2)') trim(line), phase(k)
    end do
    ! each pair of bodies with a law at t = 0: its entries and facing surface nodes
    line = trim(line)//','
    do k = 1, size(c0%pair_touch)
      write(line, '(a,i0,":",i0)') trim(line)//trim(merge(' ', ';', k == 1)), &
        nint(c0%pair_touch(k)), nint(c0%pair_face(k))
    end do
    write(output_unit, '(a)') trim(line)
  end subroutine run_case

  !> Pair entries between two bodies now (the others are a body's self-contact).
  integer function body_entries() result(n)
    integer :: e
    n = 0
    do e = 1, s%wk%fc%npn
      if (s%prm%field_body(s%wk%fc%pn_a(e)) /= s%prm%field_body(s%wk%fc%pn_b(e))) n = n + 1
    end do
  end function body_entries

  !> One J2 material and one ring body (sector), one wall to be placed by the caller;
  !! 2 x 2 particles per cell.
  function scene_case(basis, scheme, E, nu, rho, sigma_y, hardening, r_inner, r_outer, &
                      n_thick, sector, velocity) result(c)
    integer, intent(in) :: basis, scheme        !! BASIS_* and SCHEME_* codes
    real(wp), intent(in) :: E, nu, rho          !! [Pa], [-], [kg/m^3]
    real(wp), intent(in) :: sigma_y, hardening  !! [Pa]
    real(wp), intent(in) :: r_inner, r_outer    !! radii [m]
    integer, intent(in) :: n_thick              !! particles through the wall
    integer, intent(in) :: sector               !! SECTOR_* code
    real(wp), intent(in) :: velocity(2)         !! initial velocity [m/s]
    type(config_t) :: c
    c = scene_new('bench', 1.0_wp, (r_outer - r_inner)/(0.5_wp*real(n_thick, wp)), basis, &
                  scheme, PLANE_STRAIN)
    c%run%cfl = 0.2_wp           ! the step of every earlier measurement (docs/performance.md)
    call scene_add_material(c, 'm', MODEL_J2, E, nu, rho, sigma_y, hardening)
    call scene_add_ring(c, [0.0_wp, 0.0_wp], r_inner, r_outer, n_thick, velocity, sector)
    call scene_add_wall(c, [0.0_wp, 0.0_wp], [0.0_wp, 1.0_wp])     ! placed by the caller
  end function scene_case

  !> One step; a failure ends the benchmark with its message.
  !> Stop with 'bench: <what>: <errmsg>' when stat is not 0 (the case's reading or set-up).
  subroutine stop_unless_ok(what)
    character(len=*), intent(in) :: what
    if (stat == 0) return
    write(error_unit, '(a)') 'bench: '//what//': '//errmsg
    error stop 2
  end subroutine stop_unless_ok

  subroutine step_or_stop()
    integer :: st
    character(len=:), allocatable :: msg
    call solver_step(s, st, msg)
    if (st /= 0) then
      write(error_unit, '(a)') 'bench: step failed: '//msg
      error stop 4
    end if
  end subroutine step_or_stop

  !> Median of a few values.
  function median(x) result(m)
    real(wp), intent(in) :: x(:)
    real(wp) :: m, y(size(x)), t
    integer :: i, j
    y = x
    do i = 2, size(y)                ! insertion sort
      t = y(i)
      j = i - 1
      do while (j >= 1)
        if (y(j) <= t) exit
        y(j + 1) = y(j)
        j = j - 1
      end do
      y(j + 1) = t
    end do
    m = 0.5_wp*(y((size(y) + 1)/2) + y(size(y)/2 + 1))
  end function median

  !> Peak resident set size of this process from /proc/self/status [bytes] (0 if unknown).
  function peak_rss() result(b)
    integer(i8) :: b, kib
    integer :: u, ios
    character(len=256) :: row
    b = 0_i8
    open(newunit=u, file='/proc/self/status', action='read', status='old', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) row
      if (ios /= 0) exit
      if (row(1:6) == 'VmHWM:') then
        read(row(7:), *, iostat=ios) kib
        if (ios == 0) b = 1024_i8*kib
        exit
      end if
    end do
    close(u, iostat=ios)
  end function peak_rss
end program bench
