!> The derived set-up as text, for --check and the banner of a run: the bodies, grid, walls,
!! time step, cost and the advice's warnings (mpm_advice).
! SPDX-License-Identifier: MIT
module mpm_report
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: SHAPE_RING, CONTACT_BONDED, basis_names, scheme_names, plane_names, &
                           volumetric_names, contact_names
  use mpm_config, only: config_t
  use mpm_bodies, only: body_report, body_fields, is_section
  use mpm_walls, only: wall_end_time, wall_travel
  use mpm_solver, only: sim_t, solver_stable_dt
  use mpm_time_step, only: time_step_dt
  use mpm_errors, only: append_msg
  use mpm_strings, only: itoa, rtoa, plural, hms, sci
  use mpm_advice, only: advice_check, cfl_text, cfl_why
  use mpm_cost, only: cost_counts_t, cost_case_counts, advice_wall_time
  use mpm_budget, only: budget_t, budget_estimate, budget_threads, bytes_text
  use mpm_sys, only: sys_memory_available
  use mpm_surface_contact, only: surface_tied
  use mpm_setup, only: sector_factor
  use mpm_body_contact, only: pair_index
  implicit none
  private
  public :: setup_report

contains

  !> The law of every pair of bodies, 'pairs 1-2 frictionless, 1-3 coulomb (0.3), ...'.
  function pair_laws_text(s) result(text)
    type(sim_t), intent(in) :: s           !! simulation (pair laws)
    character(len=:), allocatable :: text
    integer :: i, j
    text = 'pairs'
    do i = 1, s%prm%nbody - 1
      do j = i + 1, s%prm%nbody
        if (len(text) > 5) text = text//','
        text = text//' '//itoa(i)//'-'//itoa(j)//' '//trim(contact_names(s%prm%pair_law(i, j)))
        if (s%prm%pair_mu(i, j) > 0.0_wp) text = text//' ('//rtoa(s%prm%pair_mu(i, j))//')'
        if (s%prm%pair_law(i, j) == CONTACT_BONDED) text = text//' ('// &
          itoa(count(s%prm%ties%pair(1:s%prm%ties%n) == pair_index(i, j, s%prm%nbody)))// &
          ' corners tied)'
      end do
    end do
  end function pair_laws_text

  !> The walls with a stroke (when they reach it, the approach and delta/D then), with mass
  !! (the drop weight's mass and energy) and 'bonded' (the points tied to it), one line each.
  subroutine wall_motion_report(cfg, s, report)
    type(config_t), intent(in) :: cfg      !! the case
    type(sim_t), intent(in) :: s           !! the simulation at t = 0
    character(len=:), allocatable, intent(inout) :: report  !! lines appended
    integer :: k, m, ib
    real(wp) :: delta, fac, d_mean, tm
    logical :: strokes
    delta = 0.0_wp
    tm = 0.0_wp
    strokes = .false.
    do k = 1, s%nwall
      associate (w => s%walls(k))
        if (w%contact == CONTACT_BONDED) then
          if (surface_tied(s%wk%surf(k)) > 0) then
            call append_msg(report, 'wall '//itoa(k)//': bonded: '// &
              itoa(surface_tied(s%wk%surf(k)))//' surface points within h/2 of it at t = 0 '// &
              'are tied to it')
          else
            call append_msg(report, 'wall '//itoa(k)//': bonded: no surface point lies '// &
              'within h/2 of it at t = 0: nothing is tied, it acts as ''coulomb''')
          end if
        end if
        if (w%mass > 0.0_wp) then
          call append_msg(report, 'wall '//itoa(k)//': a free rigid body of '// &
            sci(cfg%walls(k)%mass, 4)//' kg (for depth '//sci(cfg%run%depth, 3)//' m) at '// &
            sci(abs(w%vn), 4)//' m/s: kinetic energy '//sci(0.5_wp*cfg%walls(k)%mass*w%vn**2, &
            4)//' J')
        else if (w%stroke > 0.0_wp) then
          strokes = .true.
          call append_msg(report, 'wall '//itoa(k)//': stroke '//sci(w%stroke, 4)// &
            ' m, easing from t = '//sci(w%t_stroke, 4)//' s, at rest from t = '// &
            sci(wall_end_time(w), 4)//' s')
          fac = 1.0_wp
          do m = 1, s%nwall
            if (s%walls(m)%mirror .and. abs(dot_product(s%walls(m)%normal, w%normal)) > &
                0.999_wp) fac = 2.0_wp
          end do
          delta = delta - fac*wall_travel(w, wall_end_time(w))
          tm = max(tm, wall_end_time(w))
        end if
      end associate
    end do
    if (.not. strokes) return
    d_mean = 0.0_wp
    do ib = size(cfg%bodies), 1, -1
      if (cfg%bodies(ib)%shape_id == SHAPE_RING) d_mean = cfg%bodies(ib)%r_inner + &
                                                          cfg%bodies(ib)%r_outer
    end do
    if (d_mean > 0.0_wp) then
      call append_msg(report, 'approach at the strokes'' end (t = '//sci(tm, 4)//' s): delta = '// &
        sci(delta, 4)//' m, delta/D = '//sci(delta/d_mean, 3)//' (D = '//sci(d_mean, 4)// &
        ' m, the mean diameter of the first ring)')
    else
      call append_msg(report, 'approach at the strokes'' end (t = '//sci(tm, 4)//' s): delta = '// &
        sci(delta, 4)//' m')
    end if
  end subroutine wall_motion_report

  !> The wall-time estimate of `steps` steps on `nthreads` threads (mpm_cost: make bench's
  !! throughput for the basis, corrected for the grid's nodes and fields, the contact, the foam
  !! and F-bar) as a report line, naming what the model counts; the long-run warning ('' none).
  subroutine wall_time_report(cfg, s, steps, nthreads, report, long_run)
    type(config_t), intent(in) :: cfg      !! the case
    type(sim_t), intent(in) :: s           !! the simulation at t = 0
    real(wp), intent(in) :: steps          !! steps to t_end [-]
    integer, intent(in) :: nthreads        !! threads of the run
    character(len=:), allocatable, intent(inout) :: report   !! the set-up, one item per line
    character(len=:), allocatable, intent(out) :: long_run   !! '' or the warning
    type(cost_counts_t) :: c
    real(wp) :: seconds, rate, bench_rate, nodes
    character(len=:), allocatable :: line, extra
    c = cost_case_counts(s)
    call advice_wall_time(steps, c, s%prm%basis, nthreads, seconds, rate, bench_rate, long_run)
    extra = '''s '//sci(bench_rate, 2)//' with '//itoa(nint(c%nodes))//' grid nodes'
    if (c%fields > 1) extra = extra//', '//itoa(c%fields)//' velocity fields'
    nodes = c%contact + c%self
    if (nodes > 0.0_wp) extra = extra//', contact at about '//itoa(nint(nodes))//' nodes a step'
    if (c%foam > 0.0_wp) extra = extra//', '//itoa(nint(c%foam))//' foam particles'
    if (c%fbar > 0.0_wp) extra = extra//', F-bar'
    line = 'wall-time estimate: about '//hms(seconds)//' (h:mm:ss, release build, '// &
      itoa(min(nthreads, 2))//' thread(s), at the '//sci(rate, 2)// &
      ' particle-steps/s modelled from make bench'//extra//'; docs/performance.md)'
    if (.not. rate > 0.0_wp) line = 'wall-time estimate: none (make bench has not measured '// &
      'basis '''//trim(basis_names(s%prm%basis))//''' yet; docs/performance.md)'
    if (cfg%run%threads == 0 .and. nthreads > 1) line = line//'; for free cores: a '// &
      'run takes one thread per core that other work does not keep busy'
    call append_msg(report, line)
  end subroutine wall_time_report

  !> The derived set-up as text lines (for --check and the run's banner), and the warnings a
  !! mechanics expert would give (mpm_advice's advice_check), one per line in `warnings`.
  subroutine setup_report(cfg, s, report, warnings)
    type(config_t), intent(in) :: cfg      !! the case
    type(sim_t), intent(in) :: s           !! the simulation at t = 0
    character(len=:), allocatable, intent(out) :: report    !! the set-up, one item per line
    character(len=:), allocatable, intent(out) :: warnings  !! warnings, one per line ('' none)
    integer :: ib, nthreads, nring, k
    logical, allocatable :: ring_particle(:)
    real(wp) :: dt_stable, dt
    real(wp) :: steps                      ! to t_end at the initial speeds [-]
    real(wp) :: avail
    type(budget_t) :: bud
    character(len=:), allocatable :: long_run, source
    logical :: known
    character(len=512) :: line
    report = ''
    write(line, '(a)') 'case '''//trim(cfg%run%title)//''' from '//trim(cfg%file)
    call append_msg(report, line)
    write(line, '(a,a,a,a,a,a,a,a,a,l1)') 'solver: basis ', trim(basis_names(s%prm%basis)), &
      ', scheme ', trim(scheme_names(s%prm%scheme)), ', plane ', trim(plane_names(s%prm%plane)), &
      ', volumetric ', trim(volumetric_names(s%prm%volumetric)), ', deterministic ', &
      cfg%solver%deterministic
    call append_msg(report, line)
    do ib = 1, size(cfg%bodies)
      line = body_report(cfg%bodies(ib), ib)
      call append_msg(report, line)
    end do
    write(line, '(a,i0,a,i0)') 'particles: ', s%p%np, ', domain corners: ', s%p%nc
    call append_msg(report, line)
    write(line, '(a,i0,a,i0,a,i0,a)') 'grid: ', s%g%nx, ' x ', s%g%ny, ' = ', s%g%nn, &
      ' nodes, h = '//sci(s%g%h, 3)//' m, from ('//sci(s%g%origin(1), 3)//', '// &
      sci(s%g%origin(2), 3)//') to ('//sci(s%g%origin(1) + s%g%h*real(s%g%nx - 1, wp), 3)// &
      ', '//sci(s%g%origin(2) + s%g%h*real(s%g%ny - 1, wp), 3)//') m'
    call append_msg(report, line)
    if (.not. s%g%fixed) call append_msg(report, '      (fitted to the bodies plus two '// &
      'cells; it grows when the material moves out)')
    if (s%prm%nf > 1 .and. s%prm%nbody > 1) then
      if (allocated(s%prm%self_bond)) then
        call append_msg(report, 'contact between bodies: '//itoa(s%prm%nf)//' velocity '// &
          'fields (one per body, two for a ring with self-contact), '//pair_laws_text(s))
      else
        call append_msg(report, 'contact between bodies: '//itoa(s%prm%nf)//' velocity '// &
          'fields (one per body), '//pair_laws_text(s))
      end if
    end if
    if (allocated(s%prm%self_bond)) then
      nring = count(cfg%bodies%self_contact .and. cfg%bodies%shape_id == SHAPE_RING)
      ring_particle = cfg%bodies(s%p%body(1:s%p%np))%shape_id == SHAPE_RING
      if (nring > 0) call append_msg(report, 'self-contact: '//itoa(nring)// &
        ' ring(s) split into upper and lower halves (two velocity '// &
        'fields, welded at the seams y = centre, frictionless contact elsewhere; '// &
        itoa(count(s%prm%self_bond /= 0 .and. ring_particle))//' particles bonded at the seams)')
      do k = 1, size(cfg%bodies)
        if (.not. (cfg%bodies(k)%self_contact .and. is_section(cfg%bodies(k)%shape_id))) cycle
        call append_msg(report, 'self-contact: body '//itoa(k)//': walls in '// &
          itoa(body_fields(cfg%bodies(k)))//' velocity fields (walls of one cell that share '// &
          'no joint apart), welded at the joints between them, frictionless elsewhere; '// &
          itoa(count(s%prm%self_bond /= 0 .and. s%p%body(1:s%p%np) == k))// &
          ' particles bonded at those joints')
      end do
    end if
    write(line, '(a,i0,4a)') 'walls: ', s%nwall, ' (', &
      plural(count(s%walls(:)%mirror), 'mirror plane'), ' added by the sector)'
    call append_msg(report, line)
    call wall_motion_report(cfg, s, report)
    dt_stable = solver_stable_dt(s)
    dt = dt_stable
    if (s%prm%dt_fixed > 0.0_wp) dt = s%prm%dt_fixed
    steps = s%prm%t_end/dt                 ! a real: t_end = 1e12 s must not overflow a count
    if (steps < 1.0e15_wp) steps = real(ceiling(steps, i8), wp)
    write(line, '(a,f5.3,a)') 'time step: stable limit '// &
      sci(time_step_dt(1.0_wp, s%g%h, s%prm%c_max, s%vmax), 4)//' s (cfl = 1), used '// &
      sci(dt, 4)//' s (cfl ', dt*(s%prm%c_max + s%vmax)/s%g%h, '), wave speed '//sci(s%prm%c_max, 3)//' m/s'
    call append_msg(report, line)
    if (s%prm%dt_fixed > 0.0_wp) then
      call append_msg(report, 'cfl: not used (fixed dt)')
    else if (cfg%run%cfl > 0.0_wp) then
      call append_msg(report, 'cfl: '//cfl_text(cfg%run%cfl)//', as given')
    else
      call append_msg(report, 'cfl: '//cfl_why(cfg, s%prm%cfl))
    end if
    if (steps < 1.0e15_wp) then
      write(line, '(a,i0,a)') 'steps: about '//sci(steps, 4)//' to t_end (', nint(steps, i8), &
        ' at the initial speeds)'
    else
      line = 'steps: about '//sci(steps, 4)//' to t_end at the initial speeds'
    end if
    call append_msg(report, line)
    bud = budget_estimate(cfg, budget_threads(cfg))
    call sys_memory_available(avail, source, known)
    line = 'memory estimate: '//bytes_text(bud%total)//' (particles '// &
      bytes_text(bud%particle_bytes)//', grid '//bytes_text(bud%grid_bytes)
    if (cfg%grid%fitted) line = trim(line)//' with room to grow'
    line = trim(line)//')'
    if (known) line = trim(line)//' of '//bytes_text(avail)//' available'
    call append_msg(report, line)
    line = 'work estimate: '//sci(steps*real(s%p%np, wp), 4)//' particle-steps'
    call append_msg(report, line)
    nthreads = bud%threads                 ! below parallel_min particles loops run serially
    if (s%p%np < s%prm%parallel_min) nthreads = 1
    call wall_time_report(cfg, s, steps, nthreads, report, long_run)
    if (sector_factor(cfg) > 1.0_wp) then
      call append_msg(report, 'outputs: energies and masses x '// &
        itoa(nint(sector_factor(cfg)))//' and wall forces summed over mirror images (the '// &
        'whole structure; docs/output.md)')
    end if

    call advice_check(cfg, s%g%h, s%prm%c_max, s%vmax, dt, s%walls(1:s%nwall), warnings)
    if (len(long_run) > 0) call append_msg(warnings, long_run)
  end subroutine setup_report

end module mpm_report
