!> Tube scenes against closed forms and conservation (issue 4): elastic ring stiffness between
!! platens, plastic crush against DeRuntz & Hodge with the energy balance, elastic ring impact
!! (rebound, impulse = momentum change, contact onset), and half/quarter models against the
!! full ring. The scenes are namelist files in tests/scenes/, read through the normal input path.
! SPDX-License-Identifier: MIT
program test_scenes
  use mpm_kinds, only: wp
  use mpm_constants, only: pi
  use mpm_config, only: config_t, read_config
  use mpm_setup, only: setup_sim, sector_factor
  use mpm_solver, only: sim_t, solver_step
  use mpm_walls, only: wall_travel
  use mpm_output, only: full_force
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  character(len=*), parameter :: dir = 'tests/scenes/'

  call test_elastic_stiffness()
  call test_impact_rebound()
  call test_sectors()
  call test_plastic_crush()
  call finish_tests('test_scenes')

contains

  subroutine load(file, cfg, s)
    character(len=*), intent(in) :: file
    type(config_t), intent(out) :: cfg
    type(sim_t), intent(out) :: s
    integer :: stat
    character(len=:), allocatable :: errmsg
    call read_config(dir//file, cfg, stat, errmsg)
    call check(stat == 0, 'read '//file//': '//errmsg)
    if (stat /= 0) error stop 1
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

  !> Elastic diametral stiffness: thin-ring closed form (METHOD.md sec. 7) with Roark's
  !! thick-ring factors for hoop and shear deformation: delta = P R^3/(E I) (k1 pi/4 - 2 k2^2/pi),
  !! k1 = 1 - a + b, k2 = 1 - a, a = I/(A R^2), b = 2 F (1 + nu) a, F = 6/5 (Roark & Young,
  !! Formulas for Stress and Strain, table 9.2 case 1); plane strain E -> E/(1-nu^2),
  !! nu -> nu/(1-nu). For R/t = 10 the factors raise the compliance by 1.6 %.
  subroutine test_elastic_stiffness()
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: imp(2), t0, delta, force, R, t, E, nu, ei, a, b, k_expected, k_measured
    call begin_test('elastic ring between platens: diametral stiffness')
    call load('elastic_quarter.nml', cfg, s)
    imp = 0.0_wp
    t0 = 0.5e-3_wp                        ! the platen has stopped; average over the hold
    do while (s%t < s%prm%t_end)
      call step(s)
      if (s%t > t0) imp = imp + s%walls(1)%impulse
    end do
    delta = 2.0_wp*(-wall_travel(s%walls(1), s%t))      ! both platens in the full ring
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
    call check_close(delta, 0.5e-3_wp, 'relative platen approach 0.5 mm', rtol=1.0e-9_wp)
    call check_close(k_measured, k_expected, 'stiffness within 3 % of the closed form', &
                     rtol=0.03_wp)
  end subroutine test_elastic_stiffness

  !> Elastic ring on a rigid frictionless target: it rebounds, the impulse on the target equals
  !! m (V0 + Vr), and contact starts when the surface reaches the plane (not a cell early).
  subroutine test_impact_rebound()
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: imp(2), v0, vr, mass, t_contact, dt_contact, gap, factor
    call begin_test('elastic ring impact on a rigid target')
    call load('impact_half.nml', cfg, s)
    factor = sector_factor(cfg)
    mass = sum(s%p%mass)
    v0 = sum(s%p%mass*s%p%v(2, :))/mass
    gap = cfg%bodies(1)%center(2) - cfg%bodies(1)%r_outer
    imp = 0.0_wp
    t_contact = -1.0_wp
    dt_contact = 0.0_wp
    do while (s%t < s%prm%t_end)
      call step(s)
      imp = imp + s%walls(1)%impulse
      if (t_contact < 0.0_wp .and. abs(s%walls(1)%impulse(2)) > 0.0_wp) then
        t_contact = s%t - s%dt
        dt_contact = s%dt
      end if
    end do
    vr = sum(s%p%mass*s%p%v(2, :))/mass
    print '(a,f8.4,a,f8.4,a,f7.4,a,es11.4,a,es11.4)', '  V0 ', v0, ' m/s, rebound ', vr, &
      ' m/s, COR ', -vr/v0, ', contact at ', t_contact, ' s, expected ', gap/abs(v0)
    call check(vr > 0.0_wp, 'the ring rebounds')
    call check_close(imp(2)*factor, mass*factor*(vr - v0), 'impulse on the target = m (Vr + V0)', &
                     rtol=0.01_wp)
    call check_close(t_contact, gap/abs(v0), 'contact begins within one step of gap / V0', &
                     atol=dt_contact)
    call check(-vr/v0 > 0.5_wp .and. -vr/v0 <= 1.0_wp, 'elastic COR between 0.5 and 1')
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

  !> Nearly perfectly plastic ring crushed slowly: the force over delta/D = 0.1 ... 0.3 follows
  !! DeRuntz & Hodge, P = P0 / sqrt(1 - (delta/D)^2), P0 = 4 M0 / R, M0 = sigma0 t^2/(2 sqrt 3)
  !! (plane strain), within 10 %; kinetic energy under 5 % of the plastic work there; the energy
  !! balance closes within 2 % of the work put in.
  subroutine test_plastic_crush()
    integer, parameter :: nbin = 4
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: R, t, D, p0, x, imp(2, nbin), tin(nbin), dbin, f, ratio(nbin), kmax, bal
    real(wp) :: factor, wmax
    integer :: k
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
    do while (s%t < s%prm%t_end)
      call step(s)
      x = 2.0_wp*(-wall_travel(s%walls(1), s%t - 0.5_wp*s%dt))/D     ! mid-step delta/D
      if (x >= 0.1_wp .and. x < 0.3_wp) then
        k = min(nbin, 1 + int((x - 0.1_wp)/dbin))
        imp(:, k) = imp(:, k) + s%walls(1)%impulse
        tin(k) = tin(k) + s%dt
        kmax = max(kmax, s%e_kin/s%e_plastic)
      end if
      wmax = max(wmax, abs(s%e_external))
      bal = max(bal, abs(s%e_kin + s%e_strain + s%e_plastic + s%e_damped - s%e_external - s%e0))
    end do
    call check(all(tin > 0.0_wp), 'the crush reaches delta/D = 0.3')
    if (.not. all(tin > 0.0_wp)) return
    do k = 1, nbin
      f = dot_product(full_force(s, 1, -imp(:, k)/tin(k)), [0.0_wp, 1.0_wp])*cfg%run%depth
      x = 0.1_wp + (real(k, wp) - 0.5_wp)*dbin
      ratio(k) = f/(p0/sqrt(1.0_wp - x**2))
    end do
    print '(a,4f8.4)', '  force / DeRuntz-Hodge in delta/D bins of 0.05 from 0.1: ', ratio
    print '(a,f8.4,a,f8.4)', '  max kinetic/plastic ', kmax, ', energy balance error / work ', &
      bal/wmax
    call check_close(ratio, [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp], &
                     'force within 10 % of DeRuntz-Hodge over delta/D = 0.1-0.3', rtol=0.10_wp)
    call check(kmax < 0.05_wp, 'kinetic energy under 5 % of plastic work')
    call check(bal < 0.02_wp*wmax, 'energy balance within 2 % of the work put in')
    call check_close(s%energy_error, bal/max(s%e0, wmax), &
                     'energy_error = largest imbalance / max(E0, largest external work)', &
                     rtol=1.0e-12_wp)
    call check(factor == 4.0_wp, 'quarter model outputs scale by 4')
  end subroutine test_plastic_crush
end program test_scenes
