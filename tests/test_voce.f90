!> Tests of the Voce saturation term of the linear flow stress of mpm_material (model j2):
!! k = sigma_y + H e + Q (1 - exp(-b e)), against its closed form in pure shear, in one large
!! step and in many small ones, in plane strain and plane stress; with Cowper-Symonds, the
!! returned stress against the rate-scaled flow stress; Q = 0 the linear law unchanged.
! SPDX-License-Identifier: MIT
!
! Pure shear (L = [[0, g/2], [g/2, 0]], no spin) keeps the deviator's direction in both planes
! (sigma_xx = sigma_yy = sigma_zz = 0), so the radial return is exact: after any number of
! steps q = sqrt(3) |sigma_xy| and eqps satisfy q = 3 mu (eps - eqps) = k(eqps), eps the total
! equivalent strain. The test solves that scalar equation itself by bisection.
program test_voce
  use testing, only: begin_test, check, check_close, finish_tests
  use mpm_kinds, only: wp
  use mpm_constants, only: MODEL_J2, RATE_NONE, RATE_COWPER_SYMONDS, PLANE_STRAIN, PLANE_STRESS
  use mpm_material, only: material_t, material_cfg_t, material_from, material_stress_update, &
                          MATERIAL_OK
  implicit none

  ! an aluminium alloy: sigma_y 150 MPa saturating 80 MPa higher, b = 15, small linear part
  real(wp), parameter :: E = 70.0e9_wp, nu = 0.33_wp, rho = 2700.0_wp
  real(wp), parameter :: sy = 150.0e6_wp, H = 100.0e6_wp, Q = 80.0e6_wp, b = 15.0_wp
  real(wp), parameter :: mu = E/(2.0_wp*(1.0_wp + nu))
  integer, parameter :: planes(2) = [PLANE_STRAIN, PLANE_STRESS]
  character(len=*), parameter :: plane_label(2) = ['plane strain', 'plane stress']

  call test_curve()
  call test_rate()
  call test_no_saturation()
  call finish_tests('test_voce')

contains

  !> The material (Voce term Q, b; rate law as given).
  function voce_material(q_, rate_law) result(mat)
    real(wp), intent(in) :: q_
    integer, intent(in) :: rate_law
    type(material_t) :: mat
    mat = material_from(material_cfg_t(model_id=MODEL_J2, rate_law_id=rate_law, E=E, nu=nu, &
      rho=rho, sigma_y=sy, hardening=H, voce_q=q_, voce_b=b, cs_d=40.4_wp, cs_q=5.0_wp), &
      1.0_wp)
  end function voce_material

  !> The flow stress written out independently of the module.
  pure real(wp) function k_static(e)
    real(wp), intent(in) :: e
    k_static = sy + H*e + Q*(1.0_wp - exp(-b*e))
  end function k_static

  !> eqps of q = 3 mu (eps - eqps) = k(eqps) by bisection on [0, eps].
  real(wp) function eqps_closed(eps) result(x)
    real(wp), intent(in) :: eps
    real(wp) :: lo, hi
    integer :: it
    lo = 0.0_wp
    hi = eps
    do it = 1, 200
      x = 0.5_wp*(lo + hi)
      if (3.0_wp*mu*(eps - x) > k_static(x)) then
        lo = x
      else
        hi = x
      end if
    end do
  end function eqps_closed

  !> n steps of pure shear reaching the total equivalent strain eps.
  subroutine shear(mat, plane, eps, dt, n, sig, eqps, dwp, ok)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: plane, n
    real(wp), intent(in) :: eps, dt
    real(wp), intent(out) :: sig(4), eqps, dwp
    logical, intent(out) :: ok
    real(wp) :: L(2,2), F(2,2)
    integer :: k, stat
    L = reshape([0.0_wp, 0.5_wp, 0.5_wp, 0.0_wp], [2, 2])*sqrt(3.0_wp)*eps/(n*dt)
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    sig = 0.0_wp
    eqps = 0.0_wp
    ok = .true.
    do k = 1, n
      call material_stress_update(mat, plane, L, dt, F, sig, eqps, dwp, stat)
      ok = ok .and. stat == MATERIAL_OK
    end do
  end subroutine shear

  !> The stress-strain curve: one step to eps = 0.05 and 200 steps to eps = 0.2, both planes.
  subroutine test_curve()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, e_ref, eps
    integer :: ip, ic, n
    logical :: ok
    call begin_test('voce: pure shear against q = 3 mu (eps - eqps) = k(eqps)')
    mat = voce_material(Q, RATE_NONE)
    do ip = 1, 2
      do ic = 1, 2
        eps = merge(0.05_wp, 0.2_wp, ic == 1)
        n = merge(1, 200, ic == 1)
        call shear(mat, planes(ip), eps, 1.0e-3_wp, n, sig, eqps, dwp, ok)
        e_ref = eqps_closed(eps)
        call check(ok, plane_label(ip)//': every update converged')
        call check_close([eqps], [e_ref], plane_label(ip)//': eqps', rtol=1.0e-9_wp)
        call check_close([sqrt(3.0_wp)*abs(sig(3))], [k_static(e_ref)], plane_label(ip)// &
          ': q = k(eqps) of the closed form', rtol=1.0e-9_wp)
        call check_close(sig([1, 2, 4]), [0.0_wp, 0.0_wp, 0.0_wp], plane_label(ip)// &
          ': no normal stress in pure shear', atol=1.0e-6_wp)
      end do
      ! saturation: far beyond 1/b the tangent is H again (Q fully spent)
      call check(k_static(eqps) > sy + Q, plane_label(ip)//': saturated above sigma_y + Q')
    end do
  end subroutine test_curve

  !> With Cowper-Symonds: in one step, the returned q equals the static Voce stress times
  !! 1 + (deqps / (D dt))^(1/q), and the dissipation is q deqps.
  subroutine test_rate()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, qend, dt, kr
    integer :: ip
    logical :: ok
    call begin_test('voce with cowper_symonds: the rate-scaled flow stress')
    mat = voce_material(Q, RATE_COWPER_SYMONDS)
    dt = 1.0e-4_wp
    do ip = 1, 2
      call shear(mat, planes(ip), 0.02_wp, dt, 1, sig, eqps, dwp, ok)
      qend = sqrt(3.0_wp)*abs(sig(3))
      kr = k_static(eqps)*(1.0_wp + (eqps/(40.4_wp*dt))**(1.0_wp/5.0_wp))
      call check(ok .and. eqps > 0.0_wp, plane_label(ip)//': converged, plastic')
      call check_close([qend], [kr], plane_label(ip)//': q = k(eqps) r(rate)', rtol=1.0e-9_wp)
      call check_close([qend], [3.0_wp*mu*(0.02_wp - eqps)], plane_label(ip)// &
        ': q = 3 mu (eps - eqps)', rtol=1.0e-9_wp)
      call check_close([dwp], [qend*eqps], plane_label(ip)//': dissipation q deqps', &
        rtol=1.0e-9_wp)
      call check(qend > k_static(eqps)*1.5_wp, plane_label(ip)//': the rate raises the stress')
    end do
  end subroutine test_rate

  !> Q = 0: the linear law, q = (3 mu eps H + ... ) in closed form sy + H eqps.
  subroutine test_no_saturation()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, e_ref
    logical :: ok
    call begin_test('voce_q = 0: the linear law')
    mat = voce_material(0.0_wp, RATE_NONE)
    call shear(mat, PLANE_STRAIN, 0.05_wp, 1.0e-3_wp, 10, sig, eqps, dwp, ok)
    e_ref = (3.0_wp*mu*0.05_wp - sy)/(3.0_wp*mu + H)     ! 3 mu (eps - e) = sy + H e
    call check(ok, 'converged')
    call check_close([eqps], [e_ref], 'eqps of the linear law', rtol=1.0e-12_wp)
  end subroutine test_no_saturation
end program test_voce
