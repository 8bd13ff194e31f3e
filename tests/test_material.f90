!> Tests of mpm_material against closed forms and independent reference computations.
! SPDX-License-Identifier: MIT
program test_material
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, &
                                           ieee_is_nan
  use testing, only: begin_test, check, check_close, finish_tests
  use mpm_kinds, only: wp
  use mpm_strings, only: rtoa
  use mpm_constants, only: pi, MODEL_ELASTIC, MODEL_NEOHOOKEAN, MODEL_J2, RATE_NONE, &
                           RATE_COWPER_SYMONDS, PLANE_STRAIN, PLANE_STRESS
  use mpm_material, only: material_t, material_new, material_wave_speed, &
                          material_stress_update, material_energy_density, MATERIAL_OK
  implicit none

  ! Steel-like parameters (the steel tube of Sinaie et al. 2018) with a stronger hardening
  ! for visible slopes.
  real(wp), parameter :: E = 210.0e9_wp, nu = 0.3_wp, rho = 7800.0_wp, sy = 310.0e6_wp
  real(wp), parameter :: H = 2.0e9_wp, cs_d = 40.4_wp, cs_q = 5.0_wp
  real(wp), parameter :: eye(2,2) = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
  real(wp), parameter :: zero2(2,2) = 0.0_wp
  integer, parameter :: planes(2) = [PLANE_STRAIN, PLANE_STRESS]
  character(len=*), parameter :: plane_label(2) = ['plane strain', 'plane stress']

  call seed_random()
  call test_constants()
  call test_uniaxial_plane_stress()
  call test_pure_shear_plane_strain()
  call test_uniaxial_strain_plane_strain()
  call test_yield_surface()
  call test_extreme_increments()
  call test_reference_return()
  call test_unloading()
  call test_rotation()
  call test_cowper_symonds_steady()
  call test_no_plasticity()
  call test_neohookean()
  call test_energy()
  call test_stat()
  call finish_tests('test_material')

contains

  ! ---------------------------------------------------------------------------------------
  ! Helpers

  subroutine seed_random()
    integer :: n, i
    integer, allocatable :: seed(:)
    call random_seed(size=n)
    allocate(seed(n))
    seed = [(104729 + 7919*i, i = 1, n)]
    call random_seed(put=seed)
  end subroutine seed_random

  !> Uniform random number in [lo, hi].
  function urand(lo, hi) result(x)
    real(wp), intent(in) :: lo, hi
    real(wp) :: x
    call random_number(x)
    x = lo + (hi - lo)*x
  end function urand

  !> sqrt(3 J2) of (xx, yy, xy, zz).
  pure function von_mises(s) result(q)
    real(wp), intent(in) :: s(4)
    real(wp) :: q, p
    p = (s(1) + s(2) + s(4))/3.0_wp
    q = sqrt(1.5_wp*((s(1) - p)**2 + (s(2) - p)**2 + (s(4) - p)**2 + 2.0_wp*s(3)**2))
  end function von_mises

  !> Cowper-Symonds factor, written out independently of the module.
  pure function rate_factor(deqps, dt) result(r)
    real(wp), intent(in) :: deqps, dt
    real(wp) :: r
    r = 1.0_wp + (deqps/(cs_d*dt))**(1.0_wp/cs_q)
  end function rate_factor

  !> Reference 3-D radial return by plain bisection on the multiplier (static or rate form).
  subroutine ref_return_3d(mat, rate, dt, eqps, s, dl)
    type(material_t), intent(in) :: mat
    logical, intent(in) :: rate
    real(wp), intent(in) :: dt, eqps
    real(wp), intent(inout) :: s(4)
    real(wp), intent(out) :: dl
    real(wp) :: p, dev(4), q, k0, lo, hi, mid, g
    integer :: it
    dl = 0.0_wp
    p = (s(1) + s(2) + s(4))/3.0_wp
    dev = [s(1) - p, s(2) - p, s(3), s(4) - p]
    q = von_mises(s)
    k0 = mat%sigma_y + mat%hardening*eqps
    if (q <= k0) return
    lo = 0.0_wp
    hi = (q - k0)/(3.0_wp*mat%mu + mat%hardening)
    do it = 1, 200
      mid = 0.5_wp*(lo + hi)
      g = q - 3.0_wp*mat%mu*mid - (k0 + mat%hardening*mid)
      if (rate) g = q - 3.0_wp*mat%mu*mid - (k0 + mat%hardening*mid)*rate_factor(mid, dt)
      if (g > 0.0_wp) then
        lo = mid
      else
        hi = mid
      end if
    end do
    dl = 0.5_wp*(lo + hi)
    dev = dev*(1.0_wp - 3.0_wp*mat%mu*dl/q)
    s = [p + dev(1), p + dev(2), dev(3), p + dev(4)]
  end subroutine ref_return_3d

  !> Reference plane-stress return: 3-D trial with strain increment (dxx, dyy, dxy, dzz) and
  !! the 3-D return, with dzz found by bisection so that sigma_zz = 0.
  subroutine ref_plane_stress(mat, rate, dt, s_n, eqps, d, s, dl)
    type(material_t), intent(in) :: mat
    logical, intent(in) :: rate
    real(wp), intent(in) :: dt, s_n(4), eqps, d(3)
    real(wp), intent(out) :: s(4), dl
    real(wp) :: lo, hi, dzz
    integer :: it
    lo = -1.0_wp
    hi = 1.0_wp
    do it = 1, 120
      dzz = 0.5_wp*(lo + hi)
      call ref_trial_3d(mat, rate, dt, s_n, eqps, d, dzz, s, dl)
      if (s(4) > 0.0_wp) then
        hi = dzz
      else
        lo = dzz
      end if
    end do
    call ref_trial_3d(mat, rate, dt, s_n, eqps, d, 0.5_wp*(lo + hi), s, dl)
  end subroutine ref_plane_stress

  !> 3-D elastic trial from (xx, yy, xy, 0) with strain increment (d, ezz), then the return.
  subroutine ref_trial_3d(mat, rate, dt, s_n, eqps, d, ezz, s, dl)
    type(material_t), intent(in) :: mat
    logical, intent(in) :: rate
    real(wp), intent(in) :: dt, s_n(4), eqps, d(3), ezz
    real(wp), intent(out) :: s(4), dl
    real(wp) :: tr
    tr = d(1) + d(2) + ezz
    s(1) = s_n(1) + mat%lambda*tr + 2.0_wp*mat%mu*d(1)
    s(2) = s_n(2) + mat%lambda*tr + 2.0_wp*mat%mu*d(2)
    s(3) = s_n(3) + 2.0_wp*mat%mu*d(3)
    s(4) = mat%lambda*tr + 2.0_wp*mat%mu*ezz
    call ref_return_3d(mat, rate, dt, eqps, s, dl)
  end subroutine ref_trial_3d

  !> Neo-Hookean plane-stress thickness stretch by bisection (independent of the module).
  function ref_fzz(mat, F) result(fzz)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: F(2,2)
    real(wp) :: fzz, lo, hi, j2d, h
    integer :: it
    j2d = F(1,1)*F(2,2) - F(1,2)*F(2,1)
    lo = 1.0e-3_wp
    hi = 1.0e3_wp
    do it = 1, 200
      fzz = 0.5_wp*(lo + hi)
      h = mat%lambda*log(j2d*fzz) + mat%mu*(fzz**2 - 1.0_wp)   ! J sigma_zz
      if (h > 0.0_wp) then
        hi = fzz
      else
        lo = fzz
      end if
    end do
    fzz = 0.5_wp*(lo + hi)
  end function ref_fzz

  !> Neo-Hookean Cauchy stress for a given thickness stretch (test-side formula).
  function ref_neo_stress(mat, F, fzz) result(s)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: F(2,2), fzz
    real(wp) :: s(4), jac, b(2,2)
    jac = (F(1,1)*F(2,2) - F(1,2)*F(2,1))*fzz
    b = matmul(F, transpose(F))
    s(1) = (mat%lambda*log(jac) + mat%mu*(b(1,1) - 1.0_wp))/jac
    s(2) = (mat%lambda*log(jac) + mat%mu*(b(2,2) - 1.0_wp))/jac
    s(3) = mat%mu*b(1,2)/jac
    s(4) = (mat%lambda*log(jac) + mat%mu*(fzz**2 - 1.0_wp))/jac
  end function ref_neo_stress

  !> One update that must succeed (stat is checked by the caller through ok).
  subroutine update(mat, plane, L, dt, sig, eqps, dwp, ok)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: plane
    real(wp), intent(in) :: L(2,2), dt
    real(wp), intent(inout) :: sig(4), eqps
    real(wp), intent(out) :: dwp
    logical, intent(inout) :: ok
    integer :: stat
    call material_stress_update(mat, plane, L, dt, eye, sig, eqps, dwp, stat)
    ok = ok .and. stat == MATERIAL_OK
  end subroutine update

  ! ---------------------------------------------------------------------------------------
  ! Tests

  subroutine test_constants()
    type(material_t) :: mat
    call begin_test('derived constants')
    mat = material_new(MODEL_J2, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    call check_close(mat%mu, E/(2.0_wp*(1.0_wp + nu)), 'mu = E/(2(1+nu))', rtol=1e-14_wp)
    call check_close(mat%bulk, mat%lambda + 2.0_wp*mat%mu/3.0_wp, 'K = lambda + 2 mu/3', &
                     rtol=1e-14_wp)
    call check_close(mat%lambda + 2.0_wp*mat%mu, E*(1.0_wp - nu)/((1.0_wp + nu)* &
                     (1.0_wp - 2.0_wp*nu)), 'P-wave modulus', rtol=1e-14_wp)
    call check_close(material_wave_speed(mat), sqrt(E*(1.0_wp - nu)/(rho*(1.0_wp + nu)* &
                     (1.0_wp - 2.0_wp*nu))), 'dilatational wave speed', rtol=1e-14_wp)
  end subroutine test_constants

  !> Uniaxial stress in plane stress: sigma_yy = 0 kept by a secant iteration on the lateral
  !! strain rate. Closed form: bilinear sigma = E eps, then sigma_y + E_t (eps - eps_y).
  subroutine test_uniaxial_plane_stress()
    integer, parameter :: nstep = 600
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, eps, rate, dt, et, eps_y, syy_max, zz_xy_max
    real(wp) :: actual(nstep), expected(nstep)
    logical :: ok
    integer :: n
    call begin_test('uniaxial stress, plane stress, bilinear curve')
    mat = material_new(MODEL_J2, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    rate = 1.0_wp
    dt = 1.0e-5_wp
    eps_y = sy/E
    et = E*H/(E + H)
    sig = 0.0_wp
    eqps = 0.0_wp
    eps = 0.0_wp
    syy_max = 0.0_wp
    zz_xy_max = 0.0_wp
    ok = .true.
    do n = 1, nstep
      call uniaxial_step(mat, rate, dt, sig, eqps, dwp, ok)
      eps = eps + rate*dt          ! sum of D dt: the logarithmic strain
      actual(n) = sig(1)
      if (eps <= eps_y) then
        expected(n) = E*eps
      else
        expected(n) = sy + et*(eps - eps_y)
      end if
      syy_max = max(syy_max, abs(sig(2)))
      zz_xy_max = max(zz_xy_max, abs(sig(3)), abs(sig(4)))
    end do
    call check(ok, 'all updates stat = 0 and lateral iteration converged')
    call check(eps > 3.0_wp*eps_y, 'path reaches 3 eps_y')
    call check_close(actual, expected, 'sigma_xx = bilinear(eps)', rtol=1e-6_wp)
    call check(syy_max <= 1.0e-9_wp*sy, 'sigma_yy = 0 held by the lateral iteration')
    call check(zz_xy_max == 0.0_wp, 'sigma_xy = sigma_zz = 0 exactly')
    call check_close(eqps, eps - sig(1)/E, 'eqps = eps - sigma/E', rtol=1e-6_wp)
  end subroutine test_uniaxial_plane_stress

  !> One step of uniaxial stress: secant on the lateral rate so that sigma_yy = 0.
  subroutine uniaxial_step(mat, rate, dt, sig, eqps, dwp, ok)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: rate, dt
    real(wp), intent(inout) :: sig(4), eqps
    real(wp), intent(out) :: dwp
    logical, intent(inout) :: ok
    real(wp) :: d0, d1, d2, g0, g1, s1(4), e1
    integer :: it
    d0 = -nu*rate
    d1 = -0.5_wp*rate
    g0 = uniaxial_syy(mat, rate, dt, sig, eqps, d0, ok)
    g1 = uniaxial_syy(mat, rate, dt, sig, eqps, d1, ok)
    do it = 1, 60
      if (abs(g1) <= 1.0e-10_wp*sy .or. g1 == g0) exit
      d2 = d1 - g1*(d1 - d0)/(g1 - g0)
      d0 = d1
      g0 = g1
      d1 = d2
      g1 = uniaxial_syy(mat, rate, dt, sig, eqps, d1, ok)
    end do
    ok = ok .and. abs(g1) <= 1.0e-9_wp*sy
    s1 = sig
    e1 = eqps
    call update(mat, PLANE_STRESS, reshape([rate, 0.0_wp, 0.0_wp, d1], [2, 2]), dt, s1, e1, &
                dwp, ok)
    sig = s1
    eqps = e1
  end subroutine uniaxial_step

  !> sigma_yy after a trial step with lateral rate d (state not changed).
  function uniaxial_syy(mat, rate, dt, sig, eqps, d, ok) result(g)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: rate, dt, sig(4), eqps, d
    logical, intent(inout) :: ok
    real(wp) :: g, st(4), et, w
    st = sig
    et = eqps
    call update(mat, PLANE_STRESS, reshape([rate, 0.0_wp, 0.0_wp, d], [2, 2]), dt, st, et, w, ok)
    g = st(2)
  end function uniaxial_syy

  !> Pure shear in plane strain (L = D, W = 0): sigma_zz stays 0 and tau-gamma is bilinear,
  !! tau = mu gamma, then tau_y + mu H/(3 mu + H) (gamma - gamma_y), tau_y = sigma_y/sqrt(3).
  subroutine test_pure_shear_plane_strain()
    integer, parameter :: nstep = 600
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, gam, gdot, dt, tau_y, gam_y, normal_max
    real(wp) :: actual(nstep), expected(nstep)
    logical :: ok
    integer :: n
    call begin_test('pure shear, plane strain, bilinear tau-gamma')
    mat = material_new(MODEL_J2, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    gdot = 1.0_wp
    dt = 1.0e-5_wp
    tau_y = sy/sqrt(3.0_wp)
    gam_y = tau_y/mat%mu
    sig = 0.0_wp
    eqps = 0.0_wp
    gam = 0.0_wp
    normal_max = 0.0_wp
    ok = .true.
    do n = 1, nstep
      call update(mat, PLANE_STRAIN, reshape([0.0_wp, 0.5_wp*gdot, 0.5_wp*gdot, 0.0_wp], &
                  [2, 2]), dt, sig, eqps, dwp, ok)
      gam = gam + gdot*dt
      actual(n) = sig(3)
      if (gam <= gam_y) then
        expected(n) = mat%mu*gam
      else
        expected(n) = tau_y + mat%mu*H/(3.0_wp*mat%mu + H)*(gam - gam_y)
      end if
      normal_max = max(normal_max, abs(sig(1)), abs(sig(2)), abs(sig(4)))
    end do
    call check(ok, 'all updates stat = 0')
    call check(gam > 2.5_wp*gam_y, 'path reaches 2.5 gamma_y')
    call check_close(actual, expected, 'tau = bilinear(gamma)', rtol=1e-6_wp)
    call check(normal_max <= 1.0e-12_wp*sy, 'normal stresses incl. sigma_zz stay 0')
    call check_close(eqps, (gam - sig(3)/mat%mu)/sqrt(3.0_wp), 'eqps = gamma_p/sqrt(3)', &
                     rtol=1e-6_wp)
  end subroutine test_pure_shear_plane_strain

  !> Uniaxial strain (L = diag(rate, 0)) in plane strain: p = K eps; q = 2 mu eps, then
  !! q = sigma_y + H (2 mu eps - sigma_y)/(3 mu + H); sigma_xx = p + 2q/3, yy = zz = p - q/3.
  subroutine test_uniaxial_strain_plane_strain()
    integer, parameter :: nstep = 600
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, eps, rate, dt, q, p
    real(wp) :: act(nstep, 3), expct(nstep, 3)
    logical :: ok
    integer :: n
    call begin_test('uniaxial strain, plane strain, sigma_zz carried')
    mat = material_new(MODEL_J2, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    rate = 1.0_wp
    dt = 1.0e-5_wp
    sig = 0.0_wp
    eqps = 0.0_wp
    eps = 0.0_wp
    ok = .true.
    do n = 1, nstep
      call update(mat, PLANE_STRAIN, reshape([rate, 0.0_wp, 0.0_wp, 0.0_wp], [2, 2]), dt, &
                  sig, eqps, dwp, ok)
      eps = eps + rate*dt
      p = mat%bulk*eps
      q = 2.0_wp*mat%mu*eps
      if (q > sy) q = sy + H*(2.0_wp*mat%mu*eps - sy)/(3.0_wp*mat%mu + H)
      act(n, :) = [sig(1), sig(2), sig(4)]
      expct(n, :) = [p + 2.0_wp*q/3.0_wp, p - q/3.0_wp, p - q/3.0_wp]
    end do
    call check(ok, 'all updates stat = 0')
    call check(eqps > 0.0_wp, 'path is plastic')
    call check_close(act(:, 1), expct(:, 1), 'sigma_xx', rtol=1e-6_wp)
    call check_close(act(:, 2), expct(:, 2), 'sigma_yy', rtol=1e-6_wp)
    call check_close(act(:, 3), expct(:, 3), 'sigma_zz', rtol=1e-6_wp)
  end subroutine test_uniaxial_strain_plane_strain

  !> Random strain increments (with spin): after every plastic step |sqrt(3 J2) - yield| <=
  !! 1e-10 yield, yield incl. the rate factor of the step; dwp = yield_end * deqps.
  !! To see deqps without the rounding of eqps + deqps, each step is taken with eqps = 0 and
  !! sigma_y + H eqps folded into the material's sigma_y (the same yield function).
  subroutine test_yield_surface()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, de, dwp, L(2,2), dt, k, worst, worst_dwp, zz_max
    logical :: ok
    integer :: ip, ir, n, nplastic
    integer, parameter :: rates(2) = [RATE_NONE, RATE_COWPER_SYMONDS]
    character(len=40) :: label
    do ip = 1, 2
      do ir = 1, 2
        write(label, '(a,a,i0)') plane_label(ip), ', rate law ', rates(ir)
        call begin_test('on the yield surface after return: '//trim(label))
        sig = 0.0_wp
        eqps = 0.0_wp
        dt = 1.0e-6_wp
        nplastic = 0
        worst = 0.0_wp
        worst_dwp = 0.0_wp
        zz_max = 0.0_wp
        ok = .true.
        do n = 1, 400
          mat = material_new(MODEL_J2, rates(ir), E, nu, rho, sy + H*eqps, H, cs_d, cs_q)
          L = reshape([urand(-3.0e3_wp, 3.0e3_wp), urand(-3.0e3_wp, 3.0e3_wp), &
                       urand(-3.0e3_wp, 3.0e3_wp), urand(-3.0e3_wp, 3.0e3_wp)], [2, 2])
          de = 0.0_wp
          call update(mat, planes(ip), L, dt, sig, de, dwp, ok)
          eqps = eqps + de
          if (planes(ip) == PLANE_STRESS) zz_max = max(zz_max, abs(sig(4)))
          if (de > 0.0_wp) then
            nplastic = nplastic + 1
            k = sy + H*eqps
            if (rates(ir) == RATE_COWPER_SYMONDS) k = k*rate_factor(de, dt)
            worst = max(worst, abs(von_mises(sig) - k)/k)
            worst_dwp = max(worst_dwp, abs(dwp - k*de)/(k*de))
          else
            worst_dwp = max(worst_dwp, abs(dwp))
          end if
        end do
        call check(ok, 'all updates stat = 0')
        call check(nplastic >= 100, 'at least 100 plastic steps')
        call check(worst <= 1.0e-10_wp, '|sqrt(3 J2) - yield| <= 1e-10 yield')
        call check(worst_dwp <= 1.0e-10_wp, 'dwp = yield_end * deqps (0 when elastic)')
        if (planes(ip) == PLANE_STRESS) call check(zz_max == 0.0_wp, 'sigma_zz = 0 exactly')
      end do
    end do
  end subroutine test_yield_surface

  !> Strain increments from 1e-9 to 1e-1 per step, time steps from 1e-9 s to 1e-2 s, H = 0
  !! and H > 0, both planes, both rate laws: stat = 0 and the state on the yield surface.
  subroutine test_extreme_increments()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, de, dwp, L(2,2), dt, k, worst, hard
    logical :: ok
    integer :: ip, ir, ih, idt, ie, n, nplastic
    integer, parameter :: rates(2) = [RATE_NONE, RATE_COWPER_SYMONDS]
    real(wp), parameter :: dts(3) = [1.0e-9_wp, 1.0e-5_wp, 1.0e-2_wp]
    real(wp), parameter :: incs(5) = [1.0e-9_wp, 1.0e-6_wp, 1.0e-4_wp, 1.0e-2_wp, 1.0e-1_wp]
    call begin_test('extreme increments: stat = 0 and on the yield surface')
    ok = .true.
    worst = 0.0_wp
    nplastic = 0
    do ip = 1, 2
      do ir = 1, 2
        do ih = 1, 2
          hard = 0.0_wp
          if (ih == 2) hard = 10.0e6_wp
          do idt = 1, 3
            dt = dts(idt)
            do ie = 1, 5
              ! start on the yield surface (uniaxial strain), then random increments
              sig = 0.0_wp
              eqps = 0.0_wp
              do n = 1, 20
                mat = material_new(MODEL_J2, rates(ir), E, nu, rho, sy + hard*eqps, hard, &
                                   cs_d, cs_q)
                if (n <= 3) then
                  L = reshape([1.0e-3_wp, 0.0_wp, 0.0_wp, 0.0_wp], [2, 2])/dt
                else
                  L = reshape([urand(-1.0_wp, 1.0_wp), urand(-1.0_wp, 1.0_wp), &
                               urand(-1.0_wp, 1.0_wp), urand(-1.0_wp, 1.0_wp)], [2, 2]) &
                      *incs(ie)/dt
                end if
                de = 0.0_wp
                call update(mat, planes(ip), L, dt, sig, de, dwp, ok)
                eqps = eqps + de
                if (de > 0.0_wp) then
                  nplastic = nplastic + 1
                  k = sy + hard*eqps
                  if (rates(ir) == RATE_COWPER_SYMONDS) k = k*rate_factor(de, dt)
                  worst = max(worst, abs(von_mises(sig) - k)/k)
                end if
              end do
            end do
          end do
        end do
      end do
    end do
    call check(ok, 'all updates stat = 0')
    call check(nplastic >= 500, 'at least 500 plastic steps')
    call check(worst <= 1.0e-10_wp, '|sqrt(3 J2) - yield| <= 1e-10 yield')
  end subroutine test_extreme_increments

  !> The module's returns against an independent algorithm: 3-D return by bisection, and for
  !! plane stress that return wrapped in a bisection on the thickness strain increment.
  subroutine test_reference_return()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, e_mod, dwp, L(2,2), dt, d(3), s_mod(4), s_ref(4), dl, tr, worst_s
    real(wp) :: worst_e
    logical :: ok, rate
    integer :: ip, ir, n, nplastic
    integer, parameter :: rates(2) = [RATE_NONE, RATE_COWPER_SYMONDS]
    character(len=40) :: label
    do ip = 1, 2
      do ir = 1, 2
        write(label, '(a,a,i0)') plane_label(ip), ', rate law ', rates(ir)
        call begin_test('return vs independent reference: '//trim(label))
        mat = material_new(MODEL_J2, rates(ir), E, nu, rho, sy, H, cs_d, cs_q)
        rate = rates(ir) == RATE_COWPER_SYMONDS
        sig = 0.0_wp
        eqps = 0.0_wp
        dt = 1.0e-6_wp
        ok = .true.
        worst_s = 0.0_wp
        worst_e = 0.0_wp
        nplastic = 0
        do n = 1, 60
          d = [urand(-2.0e-3_wp, 2.0e-3_wp), urand(-2.0e-3_wp, 2.0e-3_wp), &
               urand(-2.0e-3_wp, 2.0e-3_wp)]
          L = reshape([d(1), d(3), d(3), d(2)], [2, 2])/dt    ! symmetric: no spin
          s_mod = sig
          e_mod = eqps
          call update(mat, planes(ip), L, dt, s_mod, e_mod, dwp, ok)
          if (planes(ip) == PLANE_STRAIN) then
            tr = d(1) + d(2)
            s_ref = sig + [mat%lambda*tr + 2.0_wp*mat%mu*d(1), mat%lambda*tr + &
                           2.0_wp*mat%mu*d(2), 2.0_wp*mat%mu*d(3), mat%lambda*tr]
            call ref_return_3d(mat, rate, dt, eqps, s_ref, dl)
          else
            call ref_plane_stress(mat, rate, dt, sig, eqps, d, s_ref, dl)
          end if
          if (dl > 0.0_wp) nplastic = nplastic + 1
          worst_s = max(worst_s, maxval(abs(s_mod - s_ref))/sy)
          worst_e = max(worst_e, abs((e_mod - eqps) - dl)/max(dl, 1.0e-6_wp))
          sig = s_mod
          eqps = e_mod
        end do
        call check(ok, 'all updates stat = 0')
        call check(nplastic >= 20, 'at least 20 plastic steps')
        call check(worst_s <= 1.0e-9_wp, 'stress = reference (1e-9 sigma_y)')
        call check(worst_e <= 1.0e-9_wp, 'deqps = reference (1e-9 relative)')
      end do
    end do
  end subroutine test_reference_return

  !> Unloading from a plastic state is elastic: the stress change is the elastic law written
  !! out with E and nu, eqps does not change, dwp = 0.
  subroutine test_unloading()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, e0, dwp, dt, s0(4), de(3), dsig(4), nrm, tr, c
    logical :: ok
    integer :: ip, n
    do ip = 1, 2
      call begin_test('elastic unloading from a plastic state, '//plane_label(ip))
      mat = material_new(MODEL_J2, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
      sig = 0.0_wp
      eqps = 0.0_wp
      dt = 1.0e-5_wp
      ok = .true.
      do n = 1, 300
        call update(mat, planes(ip), reshape([1.0_wp, 0.3_wp, 0.3_wp, -0.4_wp], [2, 2]), dt, &
                    sig, eqps, dwp, ok)
      end do
      call check(eqps > 0.0_wp, 'loading path is plastic')
      s0 = sig
      e0 = eqps
      ! Unload along minus the in-plane stress direction, plus a random volumetric part.
      nrm = sqrt(sig(1)**2 + sig(2)**2 + 2.0_wp*sig(3)**2)
      de = -3.0e-4_wp*[sig(1), sig(2), sig(3)]/nrm
      c = urand(-1.0e-4_wp, 1.0e-4_wp)
      de(1:2) = de(1:2) + c
      call update(mat, planes(ip), reshape([de(1), de(3), de(3), de(2)], [2, 2])/dt, dt, sig, &
                  eqps, dwp, ok)
      tr = de(1) + de(2)
      if (planes(ip) == PLANE_STRAIN) then
        c = E*nu/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
        dsig = [c*tr + E/(1.0_wp + nu)*de(1), c*tr + E/(1.0_wp + nu)*de(2), &
                E/(1.0_wp + nu)*de(3), c*tr]
      else
        c = E/(1.0_wp - nu**2)
        dsig = [c*(de(1) + nu*de(2)), c*(de(2) + nu*de(1)), E/(1.0_wp + nu)*de(3), 0.0_wp]
      end if
      call check(ok, 'all updates stat = 0')
      call check_close(sig - s0, dsig, 'stress change = elastic law', rtol=1e-10_wp, &
                       atol=1.0e-12_wp*sy)
      call check(eqps == e0, 'eqps unchanged')
      call check(dwp == 0.0_wp, 'dwp = 0')
    end do
  end subroutine test_unloading

  !> Rigid rotation by 90 degrees in 100 steps: xx and yy swap, xy changes sign, zz and the
  !! invariants are unchanged; plus one step against Q sigma Q^T.
  subroutine test_rotation()
    type(material_t) :: mat
    real(wp) :: sig(4), s0(4), eqps, dwp, w, dt, L(2,2), q(2,2), m(2,2), th, scale, e0
    logical :: ok
    integer :: ip, im, n
    integer, parameter :: models(2) = [MODEL_ELASTIC, MODEL_J2]
    character(len=7), parameter :: model_label(2) = ['elastic', 'j2     ']
    real(wp), parameter :: small(6) = [1.0e-7_wp, -2.5e-5_wp, 1.0e-3_wp, -3.0e-3_wp, &
                                       3.9e-3_wp, 4.0e-3_wp]
    s0 = [120.0e6_wp, -40.0e6_wp, 75.0e6_wp, 30.0e6_wp]
    dt = 1.0e-4_wp
    w = pi/200.0_wp/dt
    L = reshape([0.0_wp, w, -w, 0.0_wp], [2, 2])     ! L = [[0, -w], [w, 0]]
    do ip = 1, 2
      do im = 1, 2
        call begin_test('rigid rotation by 90 degrees: '//trim(model_label(im))//', '// &
                        plane_label(ip))
        mat = material_new(models(im), RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
        sig = s0
        if (planes(ip) == PLANE_STRESS) sig(4) = 0.0_wp
        scale = maxval(abs(sig))
        eqps = 0.0_wp
        ok = .true.
        do n = 1, 100
          call update(mat, planes(ip), L, dt, sig, eqps, dwp, ok)
        end do
        call check(ok, 'all updates stat = 0')
        call check_close(sig(1) + sig(2), s0(1) + s0(2), 'trace unchanged', rtol=1e-8_wp)
        call check_close(sig(1)*sig(2) - sig(3)**2, s0(1)*s0(2) - s0(3)**2, &
                         'in-plane determinant unchanged', rtol=1e-8_wp)
        if (planes(ip) == PLANE_STRAIN) then
          call check_close(sig, [s0(2), s0(1), -s0(3), s0(4)], 'tensor rotated by 90 deg', &
                           rtol=1e-8_wp, atol=1e-8_wp*scale)
        else
          call check_close(sig, [s0(2), s0(1), -s0(3), 0.0_wp], 'tensor rotated by 90 deg', &
                           rtol=1e-8_wp, atol=1e-8_wp*scale)
        end if
        call check(eqps == 0.0_wp, 'no plastic strain')
      end do
    end do

    call begin_test('one rotation step equals Q sigma Q^T')
    mat = material_new(MODEL_ELASTIC, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    th = 0.7_wp
    q = reshape([cos(th), sin(th), -sin(th), cos(th)], [2, 2])
    m = matmul(q, matmul(reshape([s0(1), s0(3), s0(3), s0(2)], [2, 2]), transpose(q)))
    sig = s0
    ok = .true.
    call update(mat, PLANE_STRAIN, reshape([0.0_wp, th, -th, 0.0_wp], [2, 2]), 1.0_wp, sig, &
                eqps, dwp, ok)
    call check(ok, 'stat = 0')
    call check_close(sig, [m(1,1), m(2,2), m(1,2), s0(4)], 'matches Q sigma Q^T', &
                     rtol=1e-14_wp, atol=1e-14_wp*maxval(abs(s0)))
    ! small angles (a typical step turns by about 1e-4) to a few units of round-off
    do n = 1, size(small)
      th = small(n)
      q = reshape([cos(th), sin(th), -sin(th), cos(th)], [2, 2])
      m = matmul(q, matmul(reshape([s0(1), s0(3), s0(3), s0(2)], [2, 2]), transpose(q)))
      sig = s0
      call update(mat, PLANE_STRAIN, reshape([0.0_wp, th, -th, 0.0_wp], [2, 2]), 1.0_wp, &
                  sig, eqps, dwp, ok)
      call check(ok, 'stat = 0')
      call check_close(sig, [m(1,1), m(2,2), m(1,2), s0(4)], 'small angle '//rtoa(th)// &
                       ': matches Q sigma Q^T', rtol=0.0_wp, atol=1e-15_wp*maxval(abs(s0)))
    end do

    call begin_test('rotating a state on the yield surface adds no plastic strain')
    mat = material_new(MODEL_J2, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    sig = 0.0_wp
    eqps = 0.0_wp
    ok = .true.
    do n = 1, 200
      call update(mat, PLANE_STRAIN, reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [2, 2]), &
                  1.0e-5_wp, sig, eqps, dwp, ok)
    end do
    e0 = eqps
    s0 = sig
    do n = 1, 100
      call update(mat, PLANE_STRAIN, L, dt, sig, eqps, dwp, ok)
    end do
    call check(ok .and. e0 > 0.0_wp, 'stat = 0 and initial state plastic')
    call check(abs(eqps - e0) <= 1.0e-14_wp, 'eqps changes by rounding only')
    call check_close(von_mises(sig), von_mises(s0), 'sqrt(3 J2) unchanged', rtol=1e-12_wp)
  end subroutine test_rotation

  !> Cowper-Symonds at constant plastic strain rate: steady pure shear with H = 0 reaches the
  !! flow stress sigma_y (1 + (rate/D)^(1/q)), rate = gamma_dot/sqrt(3).
  subroutine test_cowper_symonds_steady()
    type(material_t) :: mat, mat_static
    real(wp) :: sig(4), ss(4), eqps, es, dwp, dwps, gdot, dt, rate, L(2,2), fac
    logical :: ok
    integer :: ip, n
    do ip = 1, 2
      call begin_test('Cowper-Symonds steady flow stress, '//plane_label(ip))
      mat = material_new(MODEL_J2, RATE_COWPER_SYMONDS, E, nu, rho, sy, 0.0_wp, cs_d, cs_q)
      mat_static = material_new(MODEL_J2, RATE_NONE, E, nu, rho, sy, 0.0_wp, cs_d, cs_q)
      rate = 100.0_wp
      gdot = sqrt(3.0_wp)*rate
      dt = 1.0e-5_wp
      L = reshape([0.0_wp, 0.5_wp*gdot, 0.5_wp*gdot, 0.0_wp], [2, 2])
      sig = 0.0_wp
      ss = 0.0_wp
      eqps = 0.0_wp
      es = 0.0_wp
      ok = .true.
      do n = 1, 300
        call update(mat, planes(ip), L, dt, sig, eqps, dwp, ok)
        call update(mat_static, planes(ip), L, dt, ss, es, dwps, ok)
      end do
      fac = 1.0_wp + (rate/cs_d)**(1.0_wp/cs_q)
      call check(ok, 'all updates stat = 0')
      call check_close(von_mises(sig), fac*sy, 'flow stress = sigma_y (1 + (rate/D)^(1/q))', &
                       rtol=1e-6_wp)
      call check_close(von_mises(sig)/von_mises(ss), fac, 'dynamic/static = closed-form factor', &
                       rtol=1e-6_wp)
      call check_close(dwp, fac*sy*rate*dt, 'dwp = flow stress * rate * dt', rtol=1e-6_wp)
    end do
  end subroutine test_cowper_symonds_steady

  !> f < 0: the J2 update equals the elastic update bit for bit, eqps and dwp untouched.
  subroutine test_no_plasticity()
    type(material_t) :: mj2, mel
    real(wp) :: s_j2(4), s_el(4), eqps_j2, eqps_el, dwp, L(2,2), dt
    logical :: ok
    integer :: ip, n
    mj2 = material_new(MODEL_J2, RATE_COWPER_SYMONDS, E, nu, rho, sy, H, cs_d, cs_q)
    mel = material_new(MODEL_ELASTIC, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    dt = 1.0e-6_wp
    do ip = 1, 2
      call begin_test('no plasticity when f < 0, '//plane_label(ip))
      ok = .true.
      s_j2 = [60.0e6_wp, -20.0e6_wp, 35.0e6_wp, 10.0e6_wp]
      if (planes(ip) == PLANE_STRESS) s_j2(4) = 0.0_wp
      s_el = s_j2
      eqps_j2 = 0.05_wp
      eqps_el = eqps_j2
      do n = 1, 20
        L = reshape([urand(-1.0e2_wp, 1.0e2_wp), urand(-1.0e2_wp, 1.0e2_wp), &
                     urand(-1.0e2_wp, 1.0e2_wp), urand(-1.0e2_wp, 1.0e2_wp)], [2, 2])
        call update(mj2, planes(ip), L, dt, s_j2, eqps_j2, dwp, ok)
        call update(mel, planes(ip), L, dt, s_el, eqps_el, dwp, ok)
      end do
      call check(ok, 'all updates stat = 0')
      call check(von_mises(s_j2) < sy, 'state stays inside the yield surface')
      call check(all(s_j2 == s_el), 'j2 stress = elastic stress exactly')
      call check(eqps_j2 == 0.05_wp, 'eqps exactly unchanged')
      call check(dwp == 0.0_wp, 'dwp = 0')
    end do
  end subroutine test_no_plasticity

  subroutine test_neohookean()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, F(2,2), s, t, lam, mu, fzz, s_ref(4), p(2,2), pnum(2,2)
    real(wp) :: fp(2,2), fm(2,2), hstep, q(2,2), m(2,2), sr(4), th
    integer :: stat, ip, i, j, k
    real(wp), parameter :: stretches(2) = [1.3_wp, 0.7_wp]
    mat = material_new(MODEL_NEOHOOKEAN, RATE_NONE, 1000.0_wp, 0.3_wp, 1000.0_wp, sy, H, &
                       cs_d, cs_q)
    lam = mat%lambda
    mu = mat%mu

    call begin_test('neohookean uniaxial stretch, plane strain')
    do k = 1, 2
      s = stretches(k)
      F = reshape([s, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
      sig = 0.0_wp
      eqps = 0.1_wp
      call material_stress_update(mat, PLANE_STRAIN, zero2, 1.0_wp, F, sig, eqps, dwp, stat)
      call check(stat == MATERIAL_OK .and. eqps == 0.1_wp .and. dwp == 0.0_wp, &
                 'stat = 0, eqps unchanged, dwp = 0')
      call check_close(sig, [(lam*log(s) + mu*(s**2 - 1.0_wp))/s, lam*log(s)/s, 0.0_wp, &
                       lam*log(s)/s], 'closed form', rtol=1e-13_wp, atol=1e-13_wp*mu)
    end do

    call begin_test('neohookean uniaxial stress, plane stress')
    do k = 1, 2
      t = stretches(k)**(-0.4_wp)                              ! lateral stretch
      s = exp(-mu*(t**2 - 1.0_wp)/lam)/t**2                    ! so that sigma_yy = 0
      F = reshape([s, 0.0_wp, 0.0_wp, t], [2, 2])
      call material_stress_update(mat, PLANE_STRESS, zero2, 1.0_wp, F, sig, eqps, dwp, stat)
      call check(stat == MATERIAL_OK, 'stat = 0')
      ! sigma_yy = sigma_zz by symmetry, so sigma_yy = 0 only if F_zz = t was found
      call check_close(sig, [mu*(s**2 - t**2)/(s*t**2), 0.0_wp, 0.0_wp, 0.0_wp], &
                       'closed form, sigma_yy = sigma_zz = 0', rtol=1e-12_wp, atol=1e-10_wp*mu)
    end do

    call begin_test('neohookean plane stress, general F, vs bisection on F_zz')
    F = reshape([1.2_wp, -0.1_wp, 0.3_wp, 0.8_wp], [2, 2])
    call material_stress_update(mat, PLANE_STRESS, zero2, 1.0_wp, F, sig, eqps, dwp, stat)
    fzz = ref_fzz(mat, F)
    s_ref = ref_neo_stress(mat, F, fzz)
    call check(stat == MATERIAL_OK, 'stat = 0')
    call check(abs(s_ref(4)) <= 1.0e-10_wp*mu, 'reference sigma_zz = 0')
    call check_close(sig, [s_ref(1:3), 0.0_wp], 'in-plane stress at the F_zz of sigma_zz = 0', &
                     rtol=1e-10_wp, atol=1e-10_wp*mu)

    call begin_test('neohookean objectivity: F -> Q F gives Q sigma Q^T')
    th = 0.4_wp
    q = reshape([cos(th), sin(th), -sin(th), cos(th)], [2, 2])
    call material_stress_update(mat, PLANE_STRAIN, zero2, 1.0_wp, F, sig, eqps, dwp, stat)
    call material_stress_update(mat, PLANE_STRAIN, zero2, 1.0_wp, matmul(q, F), sr, eqps, &
                                dwp, stat)
    m = matmul(q, matmul(reshape([sig(1), sig(3), sig(3), sig(2)], [2, 2]), transpose(q)))
    call check_close(sr, [m(1,1), m(2,2), m(1,2), sig(4)], 'rotated stress', rtol=1e-12_wp, &
                     atol=1e-12_wp*mu)

    do ip = 1, 2
      call begin_test('neohookean dW/dF (numeric) = P = J sigma F^-T, '//plane_label(ip))
      F = reshape([1.15_wp, -0.2_wp, 0.25_wp, 0.9_wp], [2, 2])
      call material_stress_update(mat, planes(ip), zero2, 1.0_wp, F, sig, eqps, dwp, stat)
      p = ref_jacobian(mat, planes(ip), F)* &
          matmul(reshape([sig(1), sig(3), sig(3), sig(2)], [2, 2]), transpose(inv2(F)))
      hstep = 1.0e-6_wp
      do j = 1, 2
        do i = 1, 2
          fp = F
          fm = F
          fp(i, j) = fp(i, j) + hstep
          fm(i, j) = fm(i, j) - hstep
          pnum(i, j) = (w_ref(mat, planes(ip), fp) - w_ref(mat, planes(ip), fm)) &
                       /(2.0_wp*hstep)
        end do
      end do
      call check(stat == MATERIAL_OK, 'stat = 0')
      call check_close(reshape(pnum, [4]), reshape(p, [4]), 'dW/dF = P', rtol=1e-6_wp, &
                       atol=1e-6_wp*mu)
    end do
  end subroutine test_neohookean

  !> J = det(F_2d) F_zz with the reference F_zz in plane stress.
  function ref_jacobian(mat, plane, G) result(jac)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: plane
    real(wp), intent(in) :: G(2,2)
    real(wp) :: jac
    jac = G(1,1)*G(2,2) - G(1,2)*G(2,1)
    if (plane == PLANE_STRESS) jac = jac*ref_fzz(mat, G)
  end function ref_jacobian

  !> Energy per reference volume from the module's per-current-volume density.
  function w_ref(mat, plane, G) result(wr)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: plane
    real(wp), intent(in) :: G(2,2)
    real(wp) :: wr
    wr = material_energy_density(mat, plane, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], G)* &
         ref_jacobian(mat, plane, G)
  end function w_ref

  pure function inv2(a) result(b)
    real(wp), intent(in) :: a(2,2)
    real(wp) :: b(2,2)
    b = reshape([a(2,2), -a(2,1), -a(1,2), a(1,1)], [2, 2])/(a(1,1)*a(2,2) - a(1,2)*a(2,1))
  end function inv2

  !> Stored energy: closed form in uniaxial stress; along random elastic paths the density
  !! equals the trapezoidal integral of sigma : D dt (exact without spin, O(w dt) with spin).
  subroutine test_energy()
    type(material_t) :: mat
    real(wp) :: sig(4), s_old(4), eqps, dwp, L(2,2), dt, d(3), integral, spin, w, F(2,2), lnj
    logical :: ok
    integer :: ip, n, is, stat
    real(wp), parameter :: spins(2) = [0.0_wp, 1.0e-2_wp]   ! spin / strain rate
    real(wp), parameter :: tols(2) = [1.0e-12_wp, 1.0e-6_wp]  ! exact / O(w dt) with spin

    call begin_test('energy density closed forms')
    mat = material_new(MODEL_ELASTIC, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    call check_close(material_energy_density(mat, PLANE_STRESS, [sy, 0.0_wp, 0.0_wp, 0.0_wp], &
                     eye), sy**2/(2.0_wp*E), 'uniaxial: sigma^2/(2E)', rtol=1e-14_wp)
    call check_close(material_energy_density(mat, PLANE_STRAIN, [0.0_wp, 0.0_wp, sy, 0.0_wp], &
                     eye), sy**2/(2.0_wp*mat%mu), 'shear: tau^2/(2 mu)', rtol=1e-14_wp)
    mat = material_new(MODEL_NEOHOOKEAN, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    call check(material_energy_density(mat, PLANE_STRAIN, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
               eye) == 0.0_wp, 'neohookean: W(I) = 0')
    ! the energy the update returns: W / J = (mu/2 (tr C - 3) - mu ln J + lambda/2 ln^2 J) / J
    F = reshape([1.1_wp, 0.0_wp, 0.0_wp, 0.95_wp], [2, 2])
    lnj = log(1.1_wp*0.95_wp)
    sig = 0.0_wp
    eqps = 0.0_wp
    call material_stress_update(mat, PLANE_STRAIN, reshape([0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                                [2, 2]), 1.0e-6_wp, F, sig, eqps, dwp, stat, w)
    call check(stat == MATERIAL_OK, 'neohookean update with energy: stat = 0')
    call check_close(w, (0.5_wp*mat%mu*(1.1_wp**2 + 0.95_wp**2 + 1.0_wp - 3.0_wp) - &
                     mat%mu*lnj + 0.5_wp*mat%lambda*lnj**2)/(1.1_wp*0.95_wp), &
                     'neohookean: W returned by the update, closed form', rtol=1e-13_wp)

    mat = material_new(MODEL_ELASTIC, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    dt = 1.0e-6_wp
    do ip = 1, 2
      do is = 1, 2
        spin = spins(is)
        if (is == 1) then
          call begin_test('W = integral of sigma:D dt, no spin, '//plane_label(ip))
        else
          call begin_test('W = integral of sigma:D dt, with spin, '//plane_label(ip))
        end if
        sig = 0.0_wp
        eqps = 0.0_wp
        integral = 0.0_wp
        ok = .true.
        do n = 1, 2000
          ! drift plus noise, so the path leaves the origin: strain increments ~ 1e-5
          d = [urand(-0.5e-5_wp, 1.0e-5_wp), urand(-1.0e-5_wp, 0.5e-5_wp), &
               urand(-0.5e-5_wp, 1.0e-5_wp)]
          L = reshape([d(1), d(3) + spin*d(1), d(3) - spin*d(1), d(2)], [2, 2])/dt
          s_old = sig
          call material_stress_update(mat, planes(ip), L, dt, eye, sig, eqps, dwp, stat, w)
          ok = ok .and. stat == MATERIAL_OK
          integral = integral + 0.5_wp*((s_old(1) + sig(1))*d(1) + (s_old(2) + sig(2))*d(2) &
                     + 2.0_wp*(s_old(3) + sig(3))*d(3))
        end do
        call check(ok, 'all updates stat = 0')
        call check_close(material_energy_density(mat, planes(ip), sig, eye), integral, &
                         'W(end) = integral', rtol=tols(is))
        call check_close(w, integral, 'W returned by the last update = integral', &
                         rtol=tols(is))
      end do
    end do
  end subroutine test_energy

  !> Pathological input gives stat /= 0 and leaves the state untouched.
  subroutine test_stat()
    type(material_t) :: mat, bad
    real(wp) :: sig(4), s0(4), eqps, dwp, L(2,2), nan, inf, w
    integer :: stat
    call begin_test('stat flag on pathological input')
    nan = ieee_value(nan, ieee_quiet_nan)
    inf = ieee_value(inf, ieee_positive_inf)
    mat = material_new(MODEL_J2, RATE_COWPER_SYMONDS, E, nu, rho, sy, H, cs_d, cs_q)
    s0 = [1.0e8_wp, 2.0e8_wp, 3.0e7_wp, 0.0_wp]

    L = 1.0_wp
    L(1,2) = nan
    sig = s0
    eqps = 0.01_wp
    call material_stress_update(mat, PLANE_STRAIN, L, 1.0e-6_wp, eye, sig, eqps, dwp, stat)
    call check(stat /= MATERIAL_OK, 'NaN in L: stat /= 0')
    call check(all(sig == s0) .and. eqps == 0.01_wp .and. dwp == 0.0_wp, &
               'NaN in L: state unchanged, dwp = 0')

    L = 1.0_wp
    L(2,1) = inf
    call material_stress_update(mat, PLANE_STRESS, L, 1.0e-6_wp, eye, sig, eqps, dwp, stat)
    call check(stat /= MATERIAL_OK .and. all(sig == s0), 'Inf in L: stat /= 0, unchanged')

    L = 1.0_wp
    call material_stress_update(mat, PLANE_STRAIN, L, inf, eye, sig, eqps, dwp, stat)
    call check(stat /= MATERIAL_OK, 'Inf dt: stat /= 0')
    call material_stress_update(mat, PLANE_STRAIN, L, -1.0e-6_wp, eye, sig, eqps, dwp, stat)
    call check(stat /= MATERIAL_OK, 'negative dt: stat /= 0')

    sig(2) = nan
    call material_stress_update(mat, PLANE_STRAIN, L, 1.0e-6_wp, eye, sig, eqps, dwp, stat)
    call check(stat /= MATERIAL_OK .and. ieee_is_nan(sig(2)), 'NaN in sigma: stat /= 0')

    sig = s0
    call material_stress_update(mat, 7, L, 1.0e-6_wp, eye, sig, eqps, dwp, stat)
    call check(stat /= MATERIAL_OK, 'unknown plane: stat /= 0')

    bad = material_new(MODEL_J2, RATE_NONE, E, nu, rho, 0.0_wp, H, cs_d, cs_q)
    call material_stress_update(bad, PLANE_STRAIN, L, 1.0e-6_wp, eye, sig, eqps, dwp, stat)
    call check(stat /= MATERIAL_OK, 'j2 with sigma_y = 0: stat /= 0')
    bad = material_new(MODEL_J2, RATE_COWPER_SYMONDS, E, nu, rho, sy, H, 0.0_wp, cs_q)
    call material_stress_update(bad, PLANE_STRESS, L, 1.0e-6_wp, eye, sig, eqps, dwp, stat)
    call check(stat /= MATERIAL_OK, 'Cowper-Symonds with D = 0: stat /= 0')

    bad = material_new(MODEL_NEOHOOKEAN, RATE_NONE, E, nu, rho, sy, H, cs_d, cs_q)
    call material_stress_update(bad, PLANE_STRESS, L, 1.0e-6_wp, &
                                reshape([1.0_wp, 0.0_wp, 0.0_wp, -0.5_wp], [2, 2]), sig, eqps, &
                                dwp, stat)
    call check(stat /= MATERIAL_OK .and. all(sig == s0), 'neohookean det F < 0: stat /= 0')
    call material_stress_update(bad, PLANE_STRAIN, L, 1.0e-6_wp, &
                                reshape([1.0_wp, nan, 0.0_wp, 1.0_wp], [2, 2]), sig, eqps, &
                                dwp, stat)
    call check(stat /= MATERIAL_OK, 'neohookean NaN in F: stat /= 0')
    w = material_energy_density(bad, PLANE_STRAIN, s0, &
                                reshape([1.0_wp, 0.0_wp, 0.0_wp, -0.5_wp], [2, 2]))
    call check(ieee_is_nan(w), 'neohookean energy with det F < 0 is NaN')
  end subroutine test_stat
end program test_material
