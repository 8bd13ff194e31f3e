!> The cost estimate made before anything is allocated (mpm_budget) and the advice on values in
!! the wrong unit and on long runs (mpm_advice), issue 15.
!! Oracles: the particle and corner counts of the set-up itself (the generators of
!! mpm_particles); the memory that the set-up and a few steps really allocate
!! (solver_memory_bytes plus the driver's copy of the particles), which the estimate must
!! bound without exceeding it by more than the growth room it adds; the refusal against a
!! given available memory on either side of the estimate; the 2^31 - 1 index limit of
!! r_outer = 26 (millimetres typed as metres); the wall-time estimate against work / rate.
!!   usage: test_budget [SCRATCH]
! SPDX-License-Identifier: MIT
program test_budget
  use mpm_kinds, only: wp
  use mpm_constants, only: MODEL_J2, MODEL_ELASTIC, SECTOR_HALF, SECTOR_QUARTER, BASIS_LINEAR, &
                           BASIS_CPDI2, EXIT_INPUT, EXIT_NUMERIC
  use mpm_config, only: config_t, config_resolve
  use mpm_scene_builder, only: scene_new, scene_add_material, scene_add_ring, scene_add_rect, &
                               scene_add_wall
  use mpm_setup, only: setup_sim
  use mpm_solver, only: sim_t, solver_step, solver_memory_bytes
  use mpm_particles, only: particles_memory_bytes
  use mpm_budget, only: budget_t, budget_estimate, budget_check, budget_max_nodes
  use mpm_cost, only: advice_wall_time, cost_counts_t
  use mpm_units, only: advice_units
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  integer :: basis

  call begin_test('estimate against the allocation')
  do basis = BASIS_LINEAR, BASIS_CPDI2
    call against_allocation(crush_quarter(basis), 'crush quarter, basis '//achar(48 + basis))
    call against_allocation(impact_half(basis), 'impact half, basis '//achar(48 + basis))
  end do
  call against_allocation(ring_and_plate(), 'ring above a plate (two bodies)')

  call begin_test('refusal against the memory available')
  call refusal()

  call begin_test('values in the wrong unit')
  call units()

  call begin_test('wall-time estimate')
  call wall_time()

  call begin_test('growth of a fitted grid limited by the memory')
  call growth_limit()

  call finish_tests('test_budget')

contains

  !> The study's crush as a quarter ring under a platen.
  function crush_quarter(basis) result(cfg)
    integer, intent(in) :: basis
    type(config_t) :: cfg
    cfg = scene_new('crush_q', 1.0e-4_wp, 0.37e-3_wp, basis=basis)
    call scene_add_material(cfg, 'steel', MODEL_J2, 210.0e9_wp, 0.3_wp, 7800.0_wp, &
                            sigma_y=310.0e6_wp, hardening=10.0e6_wp)
    call scene_add_ring(cfg, [0.0_wp, 25.43e-3_wp], 23.95e-3_wp, 25.43e-3_wp, 8, &
                        sector=SECTOR_QUARTER)
    call scene_add_wall(cfg, [0.0_wp, 50.86e-3_wp], [0.0_wp, -1.0_wp], [0.0_wp, -5.0_wp])
  end function crush_quarter

  !> The impact scene as a half ring just above the target.
  function impact_half(basis) result(cfg)
    integer, intent(in) :: basis
    type(config_t) :: cfg
    cfg = scene_new('impact_h', 1.0e-4_wp, 0.5e-3_wp, basis=basis)
    call scene_add_material(cfg, 'alu', MODEL_J2, 70.0e9_wp, 0.33_wp, 2700.0_wp, &
                            sigma_y=150.0e6_wp, hardening=200.0e6_wp)
    call scene_add_ring(cfg, [0.0_wp, 0.0262_wp], 0.024_wp, 0.026_wp, 8, &
                        velocity=[0.0_wp, -30.0_wp], sector=SECTOR_HALF)
    call scene_add_wall(cfg, [0.0_wp, 0.0_wp], [0.0_wp, 1.0_wp])
  end function impact_half

  !> A full ring falling onto an elastic plate.
  function ring_and_plate() result(cfg)
    type(config_t) :: cfg
    cfg = scene_new('ring_plate', 1.0e-4_wp, 1.0e-3_wp)
    call scene_add_material(cfg, 'alu', MODEL_ELASTIC, 70.0e9_wp, 0.33_wp, 2700.0_wp)
    call scene_add_ring(cfg, [0.0_wp, 0.03_wp], 0.024_wp, 0.026_wp, 4, &
                        velocity=[0.0_wp, -10.0_wp])
    call scene_add_rect(cfg, [0.0_wp, -0.002_wp], [0.08_wp, 0.004_wp], 80, 4)
  end function ring_and_plate

  !> Counts equal to the set-up's; the memory the set-up and 5 steps allocate (with the
  !! driver's copy of the particles) is bounded by the estimate without its fixed base, which
  !! exceeds it by no more than the growth room, the snapshot temporaries and 10 %.
  subroutine against_allocation(cfg0, what)
    type(config_t), intent(in) :: cfg0
    character(len=*), intent(in) :: what
    type(config_t) :: cfg
    type(sim_t) :: s
    type(budget_t) :: b
    integer :: stat, k
    character(len=:), allocatable :: msg, warnings
    real(wp) :: used, est, room
    cfg = cfg0
    cfg%run%threads = 1
    call config_resolve(cfg, stat, msg, warnings)
    call check(stat == 0, what//': the case is valid')
    if (stat /= 0) then
      print '(a)', msg
      return
    end if
    b = budget_estimate(cfg, 1)
    call setup_sim(cfg, s, stat, msg)
    call check(stat == 0, what//': set-up')
    if (stat /= 0) return
    call check_close(b%particles, real(s%p%np, wp), what//': particles as the set-up makes '// &
                     'them', rtol=0.0_wp)
    call check_close(b%corners, real(s%p%nc, wp), what//': corners as the set-up makes them', &
                     rtol=0.0_wp)
    do k = 1, 5
      call solver_step(s, stat, msg)
    end do
    call check(stat == 0, what//': 5 steps')
    used = real(solver_memory_bytes(s) + particles_memory_bytes(s%p), wp)
    est = b%particle_bytes + b%grid_bytes
    ! growth room: the grid of the estimate holds (nx + 2 g)(ny + 2 g) nodes against nx ny
    room = b%grid_bytes*(1.0_wp - real(s%g%nx, wp)*real(s%g%ny, wp)/b%nodes) + &
           128.0_wp*b%particles
    print '(a,3(a,f8.3),a)', what, ': allocated ', used/1048576.0_wp, ' MiB, estimate ', &
      est/1048576.0_wp, ' MiB (growth room and snapshot temporaries ', room/1048576.0_wp, ')'
    call check(est >= used, what//': the estimate bounds the allocation')
    call check(est - room <= 1.1_wp*used, what//': the estimate less its room is within '// &
               '10 % of the allocation')
  end subroutine against_allocation

  !> Refused when the estimate exceeds what is available, not when it fits; the message says
  !! both numbers and names what to change. Index overflow is refused at any memory.
  subroutine refusal()
    type(config_t) :: cfg
    type(budget_t) :: b
    integer :: stat
    character(len=:), allocatable :: msg, warnings
    cfg = impact_half(BASIS_CPDI2)
    call config_resolve(cfg, stat, msg, warnings)
    b = budget_estimate(cfg, 2)
    call budget_check(cfg, b, 2.0_wp*b%total, 'test', .true., stat, msg)
    call check(stat == 0, 'twice the estimate available: accepted')
    call budget_check(cfg, b, 0.5_wp*b%total, 'test', .false., stat, msg)
    call check(stat == 0, 'available memory unknown: accepted')
    call budget_check(cfg, b, 0.5_wp*b%total, 'the test''s number', .true., stat, msg)
    call check(stat == EXIT_INPUT, 'half the estimate available: refused (exit 2)')
    call check(index(msg, 'more than the') > 0 .and. index(msg, 'the test''s number') > 0, &
               'the message says the memory needed, what is available and from where: '//msg)
    call check(index(msg, '&grid h') > 0 .or. index(msg, 'n_thick') > 0, &
               'the message names a variable to change')
    call check(budget_max_nodes(b, 2.0_wp*b%total, .true.) > b%nodes, &
               'room for more nodes than the estimate when twice the memory is available')
    ! r_outer = 26 (mm typed in a metre field) on the crush: 1e10 nodes, beyond int32 ids
    cfg = crush_quarter(BASIS_CPDI2)
    cfg%bodies(1)%r_outer = 26.0_wp
    cfg%bodies(1)%center = [0.0_wp, 26.0_wp]
    cfg%walls(1)%point = [0.0_wp, 52.0_wp]
    call config_resolve(cfg, stat, msg, warnings)
    call check(stat == EXIT_INPUT .and. index(msg, 'r_outer = ') > 0, &
               'r_outer = 26 is refused by the reader (a likely wrong unit): '//msg)
    cfg%run%check_units = .false.          ! meant: then the budget is what refuses it
    call config_resolve(cfg, stat, msg, warnings)
    call check(stat == 0, 'r_outer = 26 with check_units = .false. passes the range checks')
    b = budget_estimate(cfg, 1)
    call check(b%nodes > 2.0_wp**31, 'r_outer = 26: more nodes than int32 ids')
    call budget_check(cfg, b, huge(1.0_wp), 'test', .true., stat, msg)
    call check(stat == EXIT_INPUT, 'r_outer = 26: refused at any memory')
    call check(index(msg, 'r_outer = 2.6000E+001 m is over 1 m') > 0, &
               'r_outer = 26: the unit hint names r_outer: '//msg)
    ! 100 000 threads on the crush: the threads' buffers are the memory, and the advice says
    ! so (before: 'a larger &grid h', for a 94 x 94 grid)
    cfg = crush_quarter(BASIS_CPDI2)
    call config_resolve(cfg, stat, msg, warnings)
    b = budget_estimate(cfg, 100000)
    call budget_check(cfg, b, 1.0e9_wp, 'test', .true., stat, msg)
    call check(stat == EXIT_INPUT .and. index(msg, 'Change: fewer &run threads (the 100000 '// &
               'threads'' scatter buffers') > 0 .and. index(msg, 'larger &grid h') == 0, &
               '100 000 threads: refused, naming the threads: '//msg)
    b = budget_estimate(cfg, 1)
    call budget_check(cfg, b, 1.0e6_wp, 'test', .true., stat, msg)
    call check(stat == EXIT_INPUT .and. index(msg, 'threads') == 0, &
               'one thread, too little memory: no word of threads: '//msg)
  end subroutine refusal

  !> One warning per implausible value, none for the study's crush.
  subroutine units()
    type(config_t) :: cfg
    character(len=:), allocatable :: text
    integer :: stat
    character(len=:), allocatable :: msg, warnings
    cfg = crush_quarter(BASIS_CPDI2)
    call config_resolve(cfg, stat, msg, warnings)
    call advice_units(cfg, text)
    call check(len(text) == 0, 'the crush as given: no unit warning ('//text//')')
    cfg%materials(1)%E = 210.0e3_wp            ! MPa typed as Pa... and a yield above E/50
    cfg%materials(1)%rho = 7.8_wp              ! g/cm^3
    cfg%grid%h = 1.5_wp
    deallocate(text)
    call advice_units(cfg, text)
    call check(index(text, 'E = 2.1000E+005 Pa is outside') > 0, 'E = 2.1e5 Pa warned')
    call check(index(text, 'sigma_y = 3.1000E+008 Pa is above E/50') > 0, &
               'sigma_y above E/50 warned')
    call check(index(text, 'rho = 7.8000E+000 kg/m^3 is outside') > 0, 'rho = 7.8 warned')
    call check(index(text, '&grid: h = 1.5000E+000 m is over 1 m') > 0, 'h = 1.5 m warned')
    call check(count_lines(text) == 4, 'four values, four lines: '//text)
    ! the reader refuses them at their variables, unless check_units = .false.
    call config_resolve(cfg, stat, msg, warnings)
    call check(stat == EXIT_INPUT .and. index(msg, '&material #1: E = ') > 0 .and. &
               index(msg, '&grid: h = ') > 0 .and. index(msg, 'check_units = .false.') > 0, &
               'config_resolve refuses the four: '//msg)
    cfg%run%check_units = .false.
    call config_resolve(cfg, stat, msg, warnings)
    call check(stat == 0, 'with check_units = .false. they are accepted: '//msg)
    cfg = crush_quarter(BASIS_CPDI2)
    cfg%materials(1)%E = 2.0e13_wp
    cfg%materials(1)%rho = 40000.0_wp
    deallocate(text)
    call advice_units(cfg, text)
    call check(index(text, 'E = 2.0000E+013') > 0 .and. index(text, 'rho = 4.0000E+004') > 0, &
               'E above 1e13 and rho above 30000 warned')
  end subroutine units

  !> A case like make bench's rings (one field, 1e6 particles, 2.6 grid nodes a particle): its
  !! rate within 5 % of make bench's for the basis; seconds = particle-steps / rate; each term
  !! of the cost model adds time (foam: none less); a warning beyond an hour only.
  subroutine wall_time()
    real(wp) :: seconds, rate, rate2, bench, more
    character(len=:), allocatable :: warning
    type(cost_counts_t) :: c, c2
    c%particles = 1.0e6_wp
    c%nodes = 2.6e6_wp
    call advice_wall_time(1.0e3_wp, c, BASIS_CPDI2, 1, seconds, rate, bench, warning)
    call check(rate > 1.0e5_wp .and. rate < 1.0e8_wp, 'a throughput between 1e5 and 1e8 '// &
               'particle-steps/s')
    call check_close(rate, bench, 'make bench''s ring: make bench''s rate', rtol=0.05_wp)
    call check_close(seconds, 1.0e9_wp/rate, 'seconds = work / rate', rtol=1.0e-14_wp)
    c%particles = 1.0e4_wp
    c%nodes = 3.0e4_wp
    call advice_wall_time(0.5_wp*3600.0_wp*rate/c%particles, c, BASIS_CPDI2, 1, seconds, rate, &
                          bench, warning)
    call check(len(warning) == 0, 'half an hour: no warning')
    call advice_wall_time(2.0_wp*3600.0_wp*rate/c%particles, c, BASIS_CPDI2, 1, seconds, rate, &
                          bench, warning)
    call check(index(warning, 'about 2:00:00') > 0, 'two hours: warned as 2:00:00: '//warning)
    call advice_wall_time(1.0e5_wp, c, BASIS_CPDI2, 8, seconds, rate2, bench, warning)
    call check(rate2 > rate, 'more threads: a higher rate (the two-thread median)')
    call advice_wall_time(1.0e5_wp, c, BASIS_CPDI2, 1, seconds, rate, bench, warning)
    c2 = c
    c2%fields = 2
    call advice_wall_time(1.0e5_wp, c2, BASIS_CPDI2, 1, more, rate2, bench, warning)
    call check(more > seconds, 'a second velocity field: more time')
    c2%contact = 100.0_wp
    call advice_wall_time(1.0e5_wp, c2, BASIS_CPDI2, 1, seconds, rate2, bench, warning)
    call check(seconds > more, 'contact between bodies: more time')
    c2%foam = c2%particles
    call advice_wall_time(1.0e5_wp, c2, BASIS_CPDI2, 1, more, rate2, bench, warning)
    call check(more >= seconds, 'foam: no less time')
    c2%fbar = c2%particles
    call advice_wall_time(1.0e5_wp, c2, BASIS_CPDI2, 1, seconds, rate2, bench, warning)
    call check(seconds > more, 'F-bar: more time')
  end subroutine wall_time

  !> A body flying away makes a fitted grid grow; with room for fewer nodes than it needs the
  !! step stops (exit 4) with a message, instead of allocating without bound.
  subroutine growth_limit()
    type(config_t) :: cfg
    type(sim_t) :: s
    integer :: stat, k
    character(len=:), allocatable :: msg, warnings
    cfg = scene_new('fly', 1.0_wp, 1.0e-3_wp)
    call scene_add_material(cfg, 'alu', MODEL_ELASTIC, 70.0e9_wp, 0.33_wp, 2700.0_wp)
    call scene_add_rect(cfg, [0.0_wp, 0.0_wp], [0.004_wp, 0.004_wp], 4, 4, &
                        velocity=[0.0_wp, 3000.0_wp])
    cfg%run%check_units = .false.          ! 3000 m/s is meant: the block must leave the grid
    call config_resolve(cfg, stat, msg, warnings)
    call check(stat == 0, 'flying block: the case resolves: '//msg)
    if (stat /= 0) return
    call setup_sim(cfg, s, stat, msg)
    call check(stat == 0, 'flying block: set-up')
    s%prm%max_nodes = 2000.0_wp
    do k = 1, 100000
      call solver_step(s, stat, msg)
      if (stat /= 0) exit
    end do
    call check(stat == EXIT_NUMERIC, 'the grid may not grow past 2000 nodes: exit 4')
    call check(index(msg, 'more than the memory available holds') > 0, 'message: '//msg)
    call check(real(s%g%nx, wp)*real(s%g%ny, wp) <= 2000.0_wp, 'the grid stayed within 2000 nodes')
  end subroutine growth_limit

  integer function count_lines(text)
    character(len=*), intent(in) :: text
    integer :: i
    count_lines = 1
    do i = 1, len(text)
      if (text(i:i) == new_line('a')) count_lines = count_lines + 1
    end do
  end function count_lines
end program test_budget
