!> Tube scenes against closed forms and conservation (issue 4): elastic ring stiffness between
!! platens, plastic crush against DeRuntz & Hodge with the energy balance, elastic ring impact
!! (rebound, impulse = momentum change, contact onset), and half/quarter models against the
!! full ring. The scenes are namelist files in tests/scenes/, read through the normal input path,
!! run here at cfl 0.6 (theirs is 0.2; every quantity checked below reads the same to 3-4
!! digits at 0.2, 0.4 and 0.6, at a third of the steps).
! SPDX-License-Identifier: MIT
program test_scenes
  use mpm_kinds, only: wp
  use mpm_constants, only: pi
  use mpm_config, only: config_t, read_config
  use mpm_setup, only: setup_sim, sector_factor
  use mpm_solver, only: sim_t, solver_step
  use mpm_walls, only: wall_travel
  use mpm_output, only: full_force, next_output
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  character(len=*), parameter :: dir = 'tests/scenes/'

  call test_next_output()
  call test_elastic_stiffness()
  call test_impact_rebound()
  call test_sectors()
  call test_plastic_crush()
  call finish_tests('test_scenes')

contains

  !> The next output time: on the grid next + k every, the first after t; an interval below a
  !! thousandth of the step, or below the round-off of t, gives the next step (and returns).
  subroutine test_next_output()
    real(wp) :: tn
    call begin_test('next output time')
    tn = next_output(1.0e-5_wp, 1.0e-5_wp, 1.00001e-5_wp)
    call check(tn == 1.0e-5_wp + 1.0e-5_wp, 'one interval on')
    tn = next_output(1.0e-5_wp, 1.0e-6_wp, 1.35e-5_wp)
    call check(tn > 1.35e-5_wp .and. tn - 1.0e-6_wp <= 1.35e-5_wp*(1.0_wp + 1.0e-12_wp) .and. &
      abs(tn - 1.4e-5_wp) < 1.0e-12_wp, 'four intervals in a step: the first after t')
    tn = next_output(1.0e-3_wp, 1.0e-15_wp, 1.0e-3_wp + 1.0e-8_wp)
    call check(tn > 1.0e-3_wp + 1.0e-8_wp .and. tn < 1.0e-3_wp + 2.0e-8_wp, &
      '1e7 intervals in a step: the next step')
    tn = next_output(10.0_wp, 1.0e-15_wp, 10.0_wp)
    call check(tn > 10.0_wp*(1.0_wp + 1.0e-12_wp) .and. tn < 10.0_wp*(1.0_wp + 2.0e-12_wp), &
      'an interval below the round-off of t: the next step, not a loop without end')
  end subroutine test_next_output

  subroutine load(file, cfg, s)
    character(len=*), intent(in) :: file
    type(config_t), intent(out) :: cfg
    type(sim_t), intent(out) :: s
    integer :: stat
    character(len=:), allocatable :: errmsg
    call read_config(dir//file, cfg, stat, errmsg)
    call check(stat == 0, 'read '//file//': '//errmsg)
    if (stat /= 0) error stop 1
    ! measured at cfl 0.2 / 0.4 / 0.6: stiffness / Roark 0.9728 / 0.9729 / 0.9729, COR 0.7711,
    ! half and quarter / full 1.0000, DeRuntz-Hodge mean 1.0447, kinetic / plastic 0.0499 /
    ! 0.0499 / 0.0498, contact onset 20.023 / 20.055 / 20.023 us (gap / V0 20.000)
    cfg%run%cfl = 0.6_wp
    call setup_sim(cfg, s, stat, errmsg)
    call check(stat == 0, 'setup '//file//': '//errmsg)
    if (stat /= 0) error stop 1
  end subroutine load

  subroutine step(s)
    type(sim_t), intent(inout) :: s
    integer :: stat
    character(len=:), allocatable :: errmsg
    call solver_step(s, stat, errmsg)
    if (stat /= 0) then
      call check(.false., 'step: '//errmsg)
      error stop 1
    end if
  end subroutine step

  !> Elastic diametral stiffness: thin-ring closed form (Roark, k1 = k2 = 1) with Roark's
  !! thick-ring factors for hoop and shear deformation: delta = P R^3/(E I) (k1 pi/4 - 2 k2^2/pi),
  !! k1 = 1 - a + b, k2 = 1 - a, a = I/(A R^2), b = 2 F (1 + nu) a, F = 6/5 (Roark & Young,
  !! Formulas for Stress and Strain, table 9.2 case 1); plane strain E -> E/(1-nu^2),
  !! nu -> nu/(1-nu). For R/t = 10 the factors raise the compliance by 1.6 %. Roark's delta
  !! is the change of the ring's diameter: the approach of its top corner (the mean over the
  !! hold), not the platen's travel, which also holds the contact's own compliance (the
  !! penalty of mpm_surface_contact, a few % of it at h = t/2: printed, not asserted).
  subroutine test_elastic_stiffness()
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: imp(2), t0, delta, force, R, t, E, nu, ei, a, b, k_expected, k_measured, &
                ytop0, ysum, tsum, d_platen
    call begin_test('elastic ring between platens: diametral stiffness')
    call load('elastic_quarter.nml', cfg, s)
    imp = 0.0_wp
    t0 = 0.5e-3_wp                        ! the platen has stopped; average over the hold
    ytop0 = maxval(s%p%xc(2, 1:s%p%nc))
    ysum = 0.0_wp
    tsum = 0.0_wp
    do while (s%t < s%prm%t_end)
      call step(s)
      if (s%t > t0) then
        imp = imp + s%walls(1)%impulse
        ysum = ysum + maxval(s%p%xc(2, 1:s%p%nc))*s%dt
        tsum = tsum + s%dt
      end if
    end do
    d_platen = 2.0_wp*(-wall_travel(s%walls(1), s%t))   ! both platens in the full ring
    delta = 2.0_wp*(ytop0 - ysum/tsum)                   ! the ring's diameter change
    force = dot_product(full_force(s, 1, -imp/(s%t - t0)), [0.0_wp, 1.0_wp])*cfg%run%depth
    associate (b1 => cfg%bodies(1), m => cfg%materials(1))
      R = 0.5_wp*(b1%r_inner + b1%r_outer)
      t = b1%r_outer - b1%r_inner
      E = m%E/(1.0_wp - m%nu**2)
      nu = m%nu/(1.0_wp - m%nu)
    end associate
    ei = E*t**3/12.0_wp
    a = t**2/(12.0_wp*R**2)
    b = 2.0_wp*1.2_wp*(1.0_wp + nu)*a
    k_expected = ei/(R**3*((1.0_wp - a + b)*pi/4.0_wp - 2.0_wp*(1.0_wp - a)**2/pi))
    k_measured = force/delta
    print '(a,es12.4,a,es12.4,a,f7.4)', '  stiffness measured ', k_measured, ' N/m/m, Roark ', &
      k_expected, ', ratio ', k_measured/k_expected
    print '(a,f7.4)', '  platen approach / ring diameter change ', d_platen/delta
    call check_close(d_platen, 0.5e-3_wp, 'relative platen approach 0.5 mm', rtol=1.0e-9_wp)
    call check(delta > 0.0_wp .and. delta < d_platen, &
               'the ring is compressed by less than the platens approach')
    call check_close(k_measured, k_expected, 'stiffness within 3 % of the closed form', &
                     rtol=0.03_wp)
  end subroutine test_elastic_stiffness

  !> Elastic ring on a rigid frictionless target: it rebounds with Bao & Yu's coefficient of
  !! restitution, and contact starts when the surface reaches the plane (not a cell early).
  !! (The impulse on the target equals m (V0 + Vr) by the scheme's momentum balance, which is
  !! no test; the closed-form impulse 2 m V of the elastic bar is in test_solver.)
  subroutine test_impact_rebound()
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: v0, vr, mass, t_contact, dt_contact, gap
    call begin_test('elastic ring impact on a rigid target')
    call load('impact_half.nml', cfg, s)
    mass = sum(s%p%mass)
    v0 = sum(s%p%mass*s%p%v(2, :))/mass
    gap = cfg%bodies(1)%center(2) - cfg%bodies(1)%r_outer
    t_contact = -1.0_wp
    dt_contact = 0.0_wp
    do while (s%t < s%prm%t_end)
      call step(s)
      if (t_contact < 0.0_wp .and. abs(s%walls(1)%impulse(2)) > 0.0_wp) then
        t_contact = s%t - s%dt
        dt_contact = s%dt
      end if
    end do
    vr = sum(s%p%mass*s%p%v(2, :))/mass
    ! the CPDI2 contact surface is the B-spline through the corners (mpm_surface_curve: the
    ! control points are shifted so that the curve meets the corner circle to O(dtheta^4)), so
    ! contact begins when the outer corners reach the plane
    print '(a,f8.4,a,f8.4,a,f7.4,a,es11.4,a,es11.4)', '  V0 ', v0, ' m/s, rebound ', vr, &
      ' m/s, COR ', -vr/v0, ', contact at ', t_contact, ' s, expected ', gap/abs(v0)
    call check(vr > 0.0_wp, 'the ring rebounds')
    call check_close(t_contact, gap/abs(v0), 'contact begins within one step of gap / V0', &
                     atol=dt_contact)
    ! Bao & Yu (2015): an elastic ring striking a rigid target at low speed rebounds with a
    ! coefficient of restitution of 0.75-0.78 (the rest of the energy stays in vibration);
    ! measured here 0.771
    call check(-vr/v0 >= 0.75_wp .and. -vr/v0 <= 0.78_wp, 'elastic COR in Bao & Yu''s '// &
               '0.75-0.78')
  end subroutine test_impact_rebound

  !> Force of the top platen of the full structure, averaged in windows of the run [N].
  subroutine windowed_force(file, nwin, fwin, delta_end)
    character(len=*), intent(in) :: file
    integer, intent(in) :: nwin
    real(wp), intent(out) :: fwin(nwin), delta_end
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: imp(2, nwin), tw
    integer :: k
    call load(file, cfg, s)
    imp = 0.0_wp
    tw = s%prm%t_end/real(nwin, wp)
    do while (s%t < s%prm%t_end)
      call step(s)
      k = min(nwin, 1 + int((s%t - 0.5_wp*s%dt)/tw))
      imp(:, k) = imp(:, k) + s%walls(1)%impulse
    end do
    do k = 1, nwin
      fwin(k) = dot_product(full_force(s, 1, -imp(:, k)/tw), [0.0_wp, 1.0_wp])*cfg%run%depth
    end do
    delta_end = -wall_travel(s%walls(1), s%t)
  end subroutine windowed_force

  !> Half and quarter models give the full ring's force within 2 %.
  subroutine test_sectors()
    integer, parameter :: nwin = 5
    real(wp) :: ffull(nwin), fhalf(nwin), fquarter(nwin), d(3)
    call begin_test('half and quarter models against the full ring')
    call windowed_force('sym_full.nml', nwin, ffull, d(1))
    call windowed_force('sym_half.nml', nwin, fhalf, d(2))
    call windowed_force('sym_quarter.nml', nwin, fquarter, d(3))
    print '(a,5es11.3)', '  full    window forces [N] ', ffull
    print '(a,5f11.4)', '  half    / full             ', fhalf/ffull
    print '(a,5f11.4)', '  quarter / full             ', fquarter/ffull
    call check_close(d(2:3), [d(1), d(1)], 'same platen travel', rtol=1.0e-12_wp)
    ! the first window holds the contact onset, compare from the second on
    call check_close(fhalf(2:), ffull(2:), 'half model force = full model force', rtol=0.02_wp)
    call check_close(fquarter(2:), ffull(2:), 'quarter model force = full model force', &
                     rtol=0.02_wp)
  end subroutine test_sectors

  !> Nearly perfectly plastic ring crushed slowly: the force over delta/D = 0.1 ... 0.3 against
  !! DeRuntz & Hodge, P = P0 / sqrt(1 - (delta/D)^2), P0 = 4 M0 / R, M0 = sigma0 t^2/(2 sqrt 3)
  !! (plane strain); kinetic energy under 5 % of the plastic work there; and the energy balance
  !! recomputed here from the particle state and the platen's force and travel, independently
  !! of the solver's energy accounts.
  subroutine test_plastic_crush()
    integer, parameter :: nbin = 4
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: R, t, D, p0, x, imp(2, nbin), tin(nbin), dbin, f, ratio(nbin), kmax, bal
    real(wp) :: factor, wmax, work, travel_old, travel, e(3), ind_bal, ind_bal_max, ind_wmax
    integer :: k, nstep
    call begin_test('plastic ring crush against DeRuntz-Hodge')
    call load('crush_quarter.nml', cfg, s)
    factor = sector_factor(cfg)
    R = 0.5_wp*(cfg%bodies(1)%r_inner + cfg%bodies(1)%r_outer)
    t = cfg%bodies(1)%r_outer - cfg%bodies(1)%r_inner
    D = 2.0_wp*R
    p0 = 4.0_wp*(cfg%materials(1)%sigma_y*t**2/(2.0_wp*sqrt(3.0_wp)))/R
    dbin = 0.2_wp/real(nbin, wp)
    imp = 0.0_wp
    tin = 0.0_wp
    kmax = 0.0_wp
    bal = 0.0_wp
    wmax = 0.0_wp
    work = 0.0_wp
    ind_bal_max = 0.0_wp
    ind_wmax = 0.0_wp
    nstep = 0
    travel_old = wall_travel(s%walls(1), s%t)
    do while (s%t < s%prm%t_end)
      call step(s)
      nstep = nstep + 1
      x = 2.0_wp*(-wall_travel(s%walls(1), s%t - 0.5_wp*s%dt))/D     ! mid-step delta/D
      if (x >= 0.1_wp .and. x < 0.3_wp) then
        k = min(nbin, 1 + int((x - 0.1_wp)/dbin))
        imp(:, k) = imp(:, k) + s%walls(1)%impulse
        tin(k) = tin(k) + s%dt
        kmax = max(kmax, s%e_kin/s%e_plastic)
      end if
      wmax = max(wmax, abs(s%e_external))
      bal = max(bal, abs(s%e_kin + s%e_strain + s%e_plastic + s%e_damped - s%e_external - s%e0))
      ! work of the platen on the ring: its mean force over the step (impulse / dt) times its
      ! displacement, the plane moving by -(travel change) along its normal
      travel = wall_travel(s%walls(1), s%t)
      work = work - (travel - travel_old)*dot_product(s%walls(1)%impulse, s%walls(1)%normal)/s%dt
      travel_old = travel
      ind_wmax = max(ind_wmax, abs(work))
      if (mod(nstep, 10) == 0 .or. s%t >= s%prm%t_end) then
        e = particle_energies(s, cfg)
        ind_bal = abs(sum(e) - work)            ! E0 = 0: the ring starts at rest, unstressed
        ind_bal_max = max(ind_bal_max, ind_bal)
      end if
    end do
    call check(all(tin > 0.0_wp), 'the crush reaches delta/D = 0.3')
    if (.not. all(tin > 0.0_wp)) return
    do k = 1, nbin
      f = dot_product(full_force(s, 1, -imp(:, k)/tin(k)), [0.0_wp, 1.0_wp])*cfg%run%depth
      x = 0.1_wp + (real(k, wp) - 0.5_wp)*dbin
      ratio(k) = f/(p0/sqrt(1.0_wp - x**2))
    end do
    e = particle_energies(s, cfg)
    print '(a,4f8.4,a,f8.4)', '  force / DeRuntz-Hodge in delta/D bins of 0.05 from 0.1: ', &
      ratio, ', mean ', sum(ratio)/real(nbin, wp)
    print '(a,f8.4,a,f8.4)', '  max kinetic/plastic ', kmax, ', energy balance error / work ', &
      bal/wmax
    print '(a,es12.5,a,es12.5,a,es12.5,a,es12.5)', '  independent: work ', work, &
      ' J/m (solver ', s%e_external, '), plastic ', e(3), ' J/m (solver ', s%e_plastic
    print '(a,f8.5,a,f8.5)', '  independent largest imbalance / work ', &
      ind_bal_max/ind_wmax, ', solver energy_error ', s%energy_error
    ! Measured 1.031, 1.044, 1.044, 1.059 (mean 1.044) with the surface contact; the node
    ! contact of before read 1.062, 1.041, 1.068, 1.093 (mean 1.066): its frozen layer at the
    ! platen stiffened the hinge there by about 2 %. At this resolution (n_t = 6, h = t/3) the
    ! crush force lies 3-6 % above DeRuntz-Hodge; the hardening of 1 MPa adds < 0.1 %.
    ! Asserted: every bin in 1.01-1.10 (the measured band with a margin of 2-3 % for the
    ! grid-crossing ripple of the bins) and the mean 1.044 +- 0.015, so a systematic shift of
    ! 2 % (the old contact's) fails.
    call check(all(ratio > 1.01_wp .and. ratio < 1.10_wp), &
               'force / DeRuntz-Hodge in 1.01-1.10 in every delta/D bin of 0.1-0.3')
    call check_close(sum(ratio)/real(nbin, wp), 1.044_wp, &
                     'mean force / DeRuntz-Hodge = 1.044 +- 0.015', atol=0.015_wp)
    call check(kmax < 0.05_wp, 'kinetic energy under 5 % of plastic work')
    call check(bal < 0.02_wp*wmax, 'energy balance within 2 % of the work put in')
    ! the independent accounts: plastic work from each particle's equivalent plastic strain
    ! and the hardening law (not the solver's dissipation sums; they differ by the elastic
    ! volume change, p/K < 0.2 %, measured 1e-5), stored energy from the stress by the bulk
    ! and shear compliances, platen work from force times travel (exact over the ramp, where
    ! the solver takes the mid-step velocity). Measured: imbalance 0.01271 here, energy_error
    ! 0.01269; the tolerance 0.001 covers sampling every 10th step here.
    call check(ind_bal_max < 0.02_wp*ind_wmax, 'independent energy balance within 2 % of the '// &
               'work put in')
    call check_close(e(3), s%e_plastic, 'plastic work from eqps = solver plastic dissipation '// &
                     '(0.1 %)', rtol=1.0e-3_wp)
    call check_close(work, s%e_external, 'platen work force x travel = solver external work '// &
                     '(1e-6)', rtol=1.0e-6_wp)
    call check_close(s%energy_error, ind_bal_max/ind_wmax, 'solver energy_error = '// &
                     'independent largest imbalance / work (+- 0.001)', atol=1.0e-3_wp)
    call check(factor == 4.0_wp, 'quarter model outputs scale by 4')
  end subroutine test_plastic_crush

  !> Kinetic, stored elastic and plastic energy of the particles [J/m], from their state alone:
  !! sum m v^2/2; sum V (p^2/(2K) + s:s/(4 mu)) with p = tr(sigma)/3 and s the deviator (3-D,
  !! sigma_zz of plane strain); sum V (sigma_y eqps + H eqps^2/2) (linear hardening, no rate law).
  function particle_energies(s, cfg) result(e)
    type(sim_t), intent(in) :: s
    type(config_t), intent(in) :: cfg
    real(wp) :: e(3)
    real(wp) :: bulk, shear, pm, dev(4), sy, hd
    integer :: ip
    associate (m => cfg%materials(1))
      bulk = m%E/(3.0_wp*(1.0_wp - 2.0_wp*m%nu))
      shear = m%E/(2.0_wp*(1.0_wp + m%nu))
      sy = m%sigma_y
      hd = m%hardening
    end associate
    e = 0.0_wp
    do ip = 1, s%p%np
      e(1) = e(1) + 0.5_wp*s%p%mass(ip)*(s%p%v(1, ip)**2 + s%p%v(2, ip)**2)
      pm = (s%p%stress(1, ip) + s%p%stress(2, ip) + s%p%stress(4, ip))/3.0_wp
      dev = [s%p%stress(1, ip) - pm, s%p%stress(2, ip) - pm, s%p%stress(3, ip), &
             s%p%stress(4, ip) - pm]
      e(2) = e(2) + s%p%vol(ip)*(0.5_wp*pm**2/bulk + (dev(1)**2 + dev(2)**2 + dev(4)**2 + &
             2.0_wp*dev(3)**2)/(4.0_wp*shear))
      e(3) = e(3) + s%p%vol(ip)*(sy*s%p%eqps(ip) + 0.5_wp*hd*s%p%eqps(ip)**2)
    end do
  end function particle_energies
end program test_scenes
