!> Tests of the crushable foam (model foam: mpm_foam through mpm_material) against closed forms:
!! the shape factor from the plastic Poisson's ratio; first yield under hydrostatic and
!! equibiaxial stress; a random strain path that stays on the yield surface with dissipation
!! >= 0, its plastic strain increments normal to the surface (associated flow); an elastic
!! load and unload back to zero stress; the uniaxial-stress path (plane stress, free sides)
!! against the hardening law and the tabulated curve, with the lateral plastic strain -nu_p
!! times the axial one; the law's continuation beyond eps_d.
! SPDX-License-Identifier: MIT
!
! The expected values are written out here from the formulas of Deshpande & Fleck (2000) and
! the hardening law, independently of the module: sigma_hat^2 = (se^2 + alpha^2 sm^2) /
! (1 + (alpha/3)^2), alpha^2 = 9 (1 - 2 nu_p) / (2 (1 + nu_p)),
! Y(e) = sigma_p + gamma e/eps_d + alpha2 ln(1 / (1 - (e/eps_d)^beta)).
program test_foam
  use testing, only: begin_test, check, check_close, finish_tests
  use mpm_kinds, only: wp
  use mpm_constants, only: MODEL_FOAM, PLANE_STRAIN, PLANE_STRESS
  use mpm_material, only: material_t, material_cfg_t, material_from, material_stress_update, &
                          MATERIAL_OK
  use mpm_foam, only: foam_alpha, foam_yield, foam_equivalent
  implicit none

  ! an Alporas-like aluminium foam (docs/method.md, Crushable foam)
  real(wp), parameter :: E = 1.0e9_wp, nu = 0.3_wp, rho = 230.0_wp
  real(wp), parameter :: sp = 1.6e6_wp, gam = 2.0e6_wp, a2 = 4.0e6_wp, bet = 4.0_wp, &
                         ed = 2.46_wp
  integer, parameter :: planes(2) = [PLANE_STRAIN, PLANE_STRESS]
  character(len=*), parameter :: plane_label(2) = ['plane strain', 'plane stress']

  call test_alpha()
  call test_hydrostatic()
  call test_random_path()
  call test_normality()
  call test_elastic_unload()
  call test_uniaxial()
  call test_beyond_eps_d()
  call finish_tests('test_foam')

contains

  !> The foam material with plastic Poisson's ratio nu_p (law), or the tabulated curve.
  function foam(nu_p, curve_e, curve_s) result(mat)
    real(wp), intent(in) :: nu_p
    real(wp), intent(in), optional :: curve_e(:), curve_s(:)
    type(material_t) :: mat
    type(material_cfg_t) :: c
    c = material_cfg_t(model_id=MODEL_FOAM, E=E, nu=nu, rho=rho, sigma_p=sp, nu_plastic=nu_p, &
                       foam_gamma=gam, foam_alpha2=a2, foam_beta=bet, eps_d=ed)
    if (present(curve_e)) then
      c%n_curve = size(curve_e)
      c%curve_strain(1:size(curve_e)) = curve_e
      c%curve_stress(1:size(curve_e)) = curve_s
    end if
    mat = material_from(c, 1.0_wp)
  end function foam

  !> The hardening law, written out.
  pure real(wp) function y_law(e)
    real(wp), intent(in) :: e
    y_law = sp + gam*e/ed + a2*log(1.0_wp/(1.0_wp - (e/ed)**bet))
  end function y_law

  pure real(wp) function alpha_of(nu_p)
    real(wp), intent(in) :: nu_p
    alpha_of = sqrt(9.0_wp*(1.0_wp - 2.0_wp*nu_p)/(2.0_wp*(1.0_wp + nu_p)))
  end function alpha_of

  !> sigma_hat of a stress (xx, yy, xy, zz), written out with the 3-D von Mises stress.
  pure real(wp) function shat(alpha, s)
    real(wp), intent(in) :: alpha, s(4)
    real(wp) :: sm, se2
    sm = (s(1) + s(2) + s(4))/3.0_wp
    se2 = 0.5_wp*((s(1) - s(2))**2 + (s(2) - s(4))**2 + (s(4) - s(1))**2) + 3.0_wp*s(3)**2
    shat = sqrt((se2 + alpha**2*sm**2)/(1.0_wp + (alpha/3.0_wp)**2))
  end function shat

  !> alpha from nu_p; nu_p = 0 gives 3/sqrt(2); uniaxial sigma_hat is |sigma|.
  subroutine test_alpha()
    real(wp) :: nup(3) = [0.0_wp, 0.1_wp, -0.2_wp]
    integer :: k
    call begin_test('foam: alpha from nu_p, sigma_hat of a uniaxial stress')
    do k = 1, 3
      call check_close(foam_alpha(nup(k)), alpha_of(nup(k)), 'alpha(nu_p)', rtol=1.0e-15_wp)
    end do
    call check_close(foam_alpha(0.0_wp), 3.0_wp/sqrt(2.0_wp), 'nu_p = 0: alpha = 2.1213', &
                     rtol=1.0e-15_wp)
    call check_close(foam_equivalent(PLANE_STRESS, 1.7_wp, [0.0_wp, -3.0e6_wp, 0.0_wp, &
      5.0_wp]), 3.0e6_wp, 'uniaxial: sigma_hat = |sigma| (plane stress ignores s_zz)', &
      rtol=1.0e-14_wp)
    call check_close(foam_equivalent(PLANE_STRAIN, 1.7_wp, [1.0e6_wp, -2.0e6_wp, 0.5e6_wp, &
      0.3e6_wp]), shat(1.7_wp, [1.0e6_wp, -2.0e6_wp, 0.5e6_wp, 0.3e6_wp]), &
      'sigma_hat of a general stress', rtol=1.0e-14_wp)
  end subroutine test_alpha

  !> Plane strain, a hydrostatic trial stress -p (L = 0: the trial is the given stress): elastic
  !! below p_y = Y sqrt(1 + (alpha/3)^2) / alpha, plastic above; after the return the stress is
  !! hydrostatic with p = Y(eqps) sqrt(1 + (alpha/3)^2) / alpha. Plane stress, equibiaxial
  !! sxx = syy = -s: first yield at s = Y sqrt((1 + (alpha/3)^2) / (1 + 4 alpha^2 / 9)).
  subroutine test_hydrostatic()
    type(material_t) :: mat
    real(wp) :: alpha, c, py, sy, sig(4), eqps, dwp, L(2,2), F(2,2), p_end
    integer :: stat, k
    call begin_test('foam: first yield under hydrostatic and equibiaxial stress')
    L = 0.0_wp
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    do k = 1, 2
      mat = foam(merge(0.0_wp, 0.2_wp, k == 1))
      alpha = alpha_of(merge(0.0_wp, 0.2_wp, k == 1))
      c = 1.0_wp + (alpha/3.0_wp)**2
      py = sp*sqrt(c)/alpha
      sig = -py*(1.0_wp - 1.0e-9_wp)*[1.0_wp, 1.0_wp, 0.0_wp, 1.0_wp]
      eqps = 0.0_wp
      call material_stress_update(mat, PLANE_STRAIN, L, 1.0e-6_wp, F, sig, eqps, dwp, stat)
      call check(stat == MATERIAL_OK .and. eqps == 0.0_wp .and. dwp == 0.0_wp, &
        'hydrostatic: elastic at (1 - 1e-9) p_y')
      sig = -py*(1.0_wp + 1.0e-9_wp)*[1.0_wp, 1.0_wp, 0.0_wp, 1.0_wp]
      call material_stress_update(mat, PLANE_STRAIN, L, 1.0e-6_wp, F, sig, eqps, dwp, stat)
      call check(stat == MATERIAL_OK .and. eqps > 0.0_wp .and. dwp > 0.0_wp, &
        'hydrostatic: plastic at (1 + 1e-9) p_y')
      ! far beyond: returned along the hydrostatic axis, on the hardened surface
      sig = -3.0_wp*py*[1.0_wp, 1.0_wp, 0.0_wp, 1.0_wp]
      eqps = 0.0_wp
      call material_stress_update(mat, PLANE_STRAIN, L, 1.0e-6_wp, F, sig, eqps, dwp, stat)
      p_end = -sig(1)
      call check(stat == MATERIAL_OK, 'hydrostatic 3 p_y: converged')
      call check_close(sig(2:4), [-p_end, 0.0_wp, -p_end], 'hydrostatic 3 p_y: stays '// &
        'hydrostatic', rtol=1.0e-13_wp, atol=1.0e-13_wp*p_end)
      call check_close(p_end, y_law(eqps)*sqrt(c)/alpha, 'hydrostatic 3 p_y: p = Y(eqps) '// &
        'sqrt(1 + (alpha/3)^2) / alpha', rtol=1.0e-10_wp)
      ! the volumetric plastic strain is alpha^2 K x sm / K... its work: p dev_p = Y deqps
      call check_close(dwp, y_law(eqps)*eqps, 'hydrostatic: dissipation Y deqps', &
                       rtol=1.0e-12_wp)
      ! plane stress, equibiaxial
      sy = sp*sqrt(c/(1.0_wp + 4.0_wp*alpha**2/9.0_wp))
      sig = -sy*(1.0_wp - 1.0e-9_wp)*[1.0_wp, 1.0_wp, 0.0_wp, 0.0_wp]
      eqps = 0.0_wp
      call material_stress_update(mat, PLANE_STRESS, L, 1.0e-6_wp, F, sig, eqps, dwp, stat)
      call check(stat == MATERIAL_OK .and. eqps == 0.0_wp, 'equibiaxial: elastic below')
      sig = -sy*(1.0_wp + 1.0e-9_wp)*[1.0_wp, 1.0_wp, 0.0_wp, 0.0_wp]
      call material_stress_update(mat, PLANE_STRESS, L, 1.0e-6_wp, F, sig, eqps, dwp, stat)
      call check(stat == MATERIAL_OK .and. eqps > 0.0_wp, 'equibiaxial: plastic above')
    end do
  end subroutine test_hydrostatic

  !> 2000 steps of a random velocity gradient (stretch, shear, spin; compression on average)
  !! in both planes, the law and a tabulated curve: after every plastic step sigma_hat =
  !! Y(eqps) within 1e-10 Y, after every elastic one sigma_hat <= Y; dissipation >= 0 and
  !! equal to Y(eqps_end) deqps (to the round-off of eqps - e0); plane stress keeps s_zz = 0.
  subroutine test_random_path()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, e0, dwp, L(2,2), F(2,2), u(4), y, dy, worst, wsum
    integer :: ip, im, k, stat, n_plastic, n_bad_surface, n_bad_work, n_inside
    integer, allocatable :: seed(:)
    logical :: ok
    call begin_test('foam: a random strain path stays on the yield surface')
    call random_seed(size=k)
    allocate(seed(k))
    seed = 12345
    call random_seed(put=seed)
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    do im = 1, 2
      if (im == 1) then
        mat = foam(0.1_wp)
      else
        mat = foam(0.0_wp, [0.0_wp, 0.2_wp, 0.8_wp, 1.6_wp], [1.5e6_wp, 1.7e6_wp, 2.5e6_wp, &
                   8.0e6_wp])
      end if
      do ip = 1, 2
        sig = 0.0_wp
        eqps = 0.0_wp
        ok = .true.
        n_plastic = 0
        n_inside = 0
        n_bad_surface = 0
        n_bad_work = 0
        worst = 0.0_wp
        wsum = 0.0_wp
        do k = 1, 2000
          call random_number(u)
          u = 2.0_wp*u - 1.0_wp
          ! strain increments up to 2e-3 (twice the yield strain) per step, mostly compressive
          L(1,1) = 1.0e-3_wp*(u(1) - 0.3_wp)
          L(2,2) = 1.0e-3_wp*(u(2) - 0.3_wp)
          L(1,2) = 1.0e-3_wp*(u(3) + 0.5_wp*u(4))
          L(2,1) = 1.0e-3_wp*(u(3) - 0.5_wp*u(4))
          e0 = eqps
          call material_stress_update(mat, planes(ip), L, 1.0_wp, F, sig, eqps, dwp, stat)
          ok = ok .and. stat == MATERIAL_OK
          if (stat /= MATERIAL_OK) exit
          call foam_yield(mat%foam, eqps, y, dy)
          if (eqps > e0) then
            n_plastic = n_plastic + 1
            worst = max(worst, abs(foam_equivalent(planes(ip), mat%alpha, sig) - y)/y)
            if (abs(foam_equivalent(planes(ip), mat%alpha, sig) - y) > 1.0e-10_wp*y) &
              n_bad_surface = n_bad_surface + 1
            if (.not. (dwp >= 0.0_wp .and. abs(dwp - y*(eqps - e0)) <= 1.0e-8_wp*dwp)) &
              n_bad_work = n_bad_work + 1
          else
            n_inside = n_inside + 1
            if (foam_equivalent(planes(ip), mat%alpha, sig) > y*(1.0_wp + 1.0e-12_wp)) &
              n_bad_surface = n_bad_surface + 1
            if (dwp /= 0.0_wp) n_bad_work = n_bad_work + 1
          end if
          wsum = wsum + dwp
        end do
        call check(ok, trim(plane_label(ip))//': every update converged')
        call check(n_plastic > 200 .and. n_inside > 200, trim(plane_label(ip))// &
          ': the path loads and unloads (plastic and elastic steps)')
        call check(n_bad_surface == 0, trim(plane_label(ip))//': on or inside the surface '// &
          'at every step (plastic: |sigma_hat - Y| <= 1e-10 Y)')
        call check(n_bad_work == 0, trim(plane_label(ip))//': dissipation Y deqps >= 0 '// &
          'at every step')
        if (planes(ip) == PLANE_STRESS) call check(sig(4) == 0.0_wp, 'plane stress: s_zz = 0')
        write(*, '(a, i0, 2a, es9.2, a, i0, a, es10.3)') '  random path, material ', im, &
          ', '//trim(plane_label(ip)), ': worst |sigma_hat - Y| / Y ', worst, &
          ', plastic steps ', n_plastic, ', eqps ', eqps
      end do
    end do
  end subroutine test_random_path

  !> Associated flow: 300 random steps without spin (the trial stress is then sigma_n + C : de,
  !! computed here), both planes, both materials: the plastic strain of every plastic step,
  !! C^-1 : (trial - returned), equals deqps n with n = d sigma_hat / d sigma at the returned
  !! stress, n = (3/2 s + alpha^2/3 sm I) / (sigma_hat (1 + (alpha/3)^2)), within 1e-9 of its
  !! size (plane stress: its in-plane part).
  subroutine test_normality()
    type(material_t) :: mat
    real(wp) :: sig(4), tr(4), ds(4), dep(4), n(4), eqps, e0, dwp, L(2,2), F(2,2), u(3), &
                lam, mu, de(3), sm, c, q, worst
    integer :: ip, im, k, stat, nplast
    call begin_test('foam: associated flow (the plastic strain is normal to the surface)')
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    mu = E/(2.0_wp*(1.0_wp + nu))
    do im = 1, 2
      mat = foam(merge(0.1_wp, 0.3_wp, im == 1))
      c = 1.0_wp + (mat%alpha/3.0_wp)**2
      do ip = 1, 2
        lam = E*nu/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
        if (planes(ip) == PLANE_STRESS) lam = E*nu/(1.0_wp - nu**2)
        sig = 0.0_wp
        eqps = 0.0_wp
        worst = 0.0_wp
        nplast = 0
        do k = 1, 300
          call random_number(u)
          de = 1.0e-3_wp*[u(1) - 0.7_wp, u(2) - 0.6_wp, u(3) - 0.5_wp]
          L = reshape([de(1), de(3), de(3), de(2)], [2, 2])
          tr = sig + [lam*(de(1) + de(2)) + 2.0_wp*mu*de(1), &
                      lam*(de(1) + de(2)) + 2.0_wp*mu*de(2), 2.0_wp*mu*de(3), &
                      lam*(de(1) + de(2))]
          if (planes(ip) == PLANE_STRESS) tr(4) = 0.0_wp
          e0 = eqps
          call material_stress_update(mat, planes(ip), L, 1.0_wp, F, sig, eqps, dwp, stat)
          if (stat /= MATERIAL_OK .or. .not. eqps > e0) cycle
          nplast = nplast + 1
          ds = tr - sig
          dep = ((1.0_wp + nu)*ds - nu*(ds(1) + ds(2) + ds(4))*[1.0_wp, 1.0_wp, 0.0_wp, &
                1.0_wp])/E
          sm = (sig(1) + sig(2) + sig(4))/3.0_wp
          q = shat(mat%alpha, sig)
          n = (1.5_wp*(sig - sm*[1.0_wp, 1.0_wp, 0.0_wp, 1.0_wp]) + mat%alpha**2/3.0_wp*sm* &
               [1.0_wp, 1.0_wp, 0.0_wp, 1.0_wp])/(q*c)
          if (planes(ip) == PLANE_STRESS) dep(4) = n(4)*(eqps - e0)   ! not compared
          worst = max(worst, maxval(abs(dep - (eqps - e0)*n))/maxval(abs(dep)))
        end do
        call check(nplast > 100, trim(plane_label(ip))//': plastic steps')
        call check(worst < 1.0e-9_wp, trim(plane_label(ip))//': plastic strain = deqps n '// &
          'within 1e-9')
        write(*, '(a, i0, 2a, es9.2)') '  normality, material ', im, ', '// &
          trim(plane_label(ip)), ': worst |deps_p - deqps n| / |deps_p| ', worst
      end do
    end do
  end subroutine test_normality

  !> Below yield, a stretch and shear without spin loaded over 50 steps and unloaded by the
  !! opposite gradient over 50: zero stress, no plastic strain.
  subroutine test_elastic_unload()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, L(2,2), F(2,2), peak
    integer :: ip, k, stat
    logical :: ok
    call begin_test('foam: elastic load and unload returns to zero stress')
    mat = foam(0.0_wp)
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    L = reshape([-6.0e-6_wp, 2.0e-6_wp, 2.0e-6_wp, -1.0e-5_wp], [2, 2])  ! sym: no spin
    do ip = 1, 2
      sig = 0.0_wp
      eqps = 0.0_wp
      ok = .true.
      do k = 1, 100
        if (k == 51) then
          L = -L
          peak = maxval(abs(sig))
        end if
        call material_stress_update(mat, planes(ip), L, 1.0_wp, F, sig, eqps, dwp, stat)
        ok = ok .and. stat == MATERIAL_OK .and. dwp == 0.0_wp
      end do
      L = -L
      call check(ok .and. eqps == 0.0_wp, trim(plane_label(ip))//': no plastic flow')
      call check(peak > 0.3_wp*sp .and. peak < sp, trim(plane_label(ip))// &
        ': the peak is elastic but not small')
      call check_close(sig, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], trim(plane_label(ip))// &
        ': zero stress after unloading', atol=1.0e-9_wp*peak)
    end do
  end subroutine test_elastic_unload

  !> Plane stress, uniaxial compression along y with a free side (sxx = 0 by a secant
  !! iteration on L11 each step), 400 steps to an axial log strain of -0.8 eps_d: at every
  !! step |syy| = Y(e) with e + Y(e)/E = |eps_yy| (the closed form: the elastic strain is
  !! syy / E), eqps = e, and the lateral plastic strain is -nu_p times the axial one.
  subroutine test_uniaxial()
    type(material_t) :: mat
    real(wp), parameter :: ce(5) = [0.0_wp, 0.1_wp, 0.5_wp, 1.2_wp, 2.0_wp], &
                           cs(5) = [1.6e6_wp, 1.65e6_wp, 2.2e6_wp, 4.0e6_wp, 9.0e6_wp]
    real(wp) :: sig(4), eqps, dwp, exx, eyy, de, nup, e_ref, y_ref, worst_y, worst_lat, &
                worst_e, ep_ax, ep_lat
    integer :: im, k, n, stat
    logical :: ok
    call begin_test('foam: uniaxial stress path against the hardening law')
    n = 400
    de = 0.8_wp*ed/n
    do im = 1, 3
      nup = merge(0.0_wp, 0.15_wp, im == 1)
      if (im <= 2) then
        mat = foam(nup)
      else
        mat = foam(nup, ce, cs)
      end if
      sig = 0.0_wp
      eqps = 0.0_wp
      exx = 0.0_wp
      eyy = 0.0_wp
      ok = .true.
      worst_y = 0.0_wp
      worst_lat = 0.0_wp
      worst_e = 0.0_wp
      do k = 1, n
        call free_side_step(mat, de, sig, eqps, dwp, exx, stat)
        ok = ok .and. stat == MATERIAL_OK
        if (stat /= MATERIAL_OK) exit
        eyy = eyy - de
        e_ref = uniaxial_closed(-eyy, im == 3)
        y_ref = merge(curve_y(e_ref), y_law(e_ref), im == 3)
        worst_y = max(worst_y, abs(-sig(2) - y_ref)/y_ref)
        worst_e = max(worst_e, abs(eqps - e_ref))
        ep_ax = eyy - sig(2)/E                    ! plastic strains: total less elastic
        ep_lat = exx + nu*sig(2)/E
        if (eqps > 0.0_wp) worst_lat = max(worst_lat, abs(ep_lat + nup*ep_ax)/abs(ep_ax))
      end do
      call check(ok, 'every update converged')
      call check(worst_y < 1.0e-9_wp, 'axial stress = Y(e) of the closed form within 1e-9')
      call check(worst_e < 1.0e-9_wp, 'eqps = the axial plastic strain within 1e-9')
      call check(worst_lat < 1.0e-8_wp, 'lateral plastic strain = -nu_p axial within 1e-8')
      call check(abs(sig(1)) < 1.0e-5_wp .and. sig(3) == 0.0_wp .and. sig(4) == 0.0_wp, &
        'uniaxial: sxx (free side), sxy, szz are 0')
      write(*, '(a, i0, a, es9.2, a, es9.2, a, es9.2, a, f7.4, a, f7.3, a)') &
        '  uniaxial, case ', im, ': worst |s - Y|/Y ', worst_y, ', |eqps - e| ', worst_e, &
        ', lateral ', worst_lat, '; at eqps ', eqps, ' s = ', -sig(2)/1.0e6_wp, ' MPa'
    end do
  end subroutine test_uniaxial

  !> One step of axial strain -de along y with sxx = 0: the lateral rate by a secant
  !! iteration on the material update (sxx increases with L11).
  subroutine free_side_step(mat, de, sig, eqps, dwp, exx, stat)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: de
    real(wp), intent(inout) :: sig(4), eqps, exx
    real(wp), intent(out) :: dwp
    integer, intent(out) :: stat
    real(wp) :: L(2,2), F(2,2), x0, x1, f0, f1, x2
    integer :: it
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    x0 = 0.0_wp
    x1 = 0.5_wp*de
    f0 = sxx_after(mat, sig, eqps, x0, de)
    f1 = sxx_after(mat, sig, eqps, x1, de)
    do it = 1, 60
      if (f1 == f0) exit
      x2 = x1 - f1*(x1 - x0)/(f1 - f0)
      x0 = x1
      f0 = f1
      x1 = x2
      f1 = sxx_after(mat, sig, eqps, x1, de)
      if (abs(f1) < 1.0e-6_wp) exit
    end do
    L = reshape([x1, 0.0_wp, 0.0_wp, -de], [2, 2])
    call material_stress_update(mat, PLANE_STRESS, L, 1.0_wp, F, sig, eqps, dwp, stat)
    exx = exx + x1
  end subroutine free_side_step

  !> sxx after a trial step with the lateral strain x and the axial strain -de [Pa].
  real(wp) function sxx_after(mat, sig, eqps, x, de) result(f)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: sig(4), eqps, x, de
    real(wp) :: s(4), e, d, L(2,2), F2(2,2)
    integer :: st
    s = sig
    e = eqps
    F2 = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    L = reshape([x, 0.0_wp, 0.0_wp, -de], [2, 2])
    call material_stress_update(mat, PLANE_STRESS, L, 1.0_wp, F2, s, e, d, st)
    f = s(1)
  end function sxx_after

  !> The tabulated curve (ce, cs of test_uniaxial), linear between its points.
  pure real(wp) function curve_y(e)
    real(wp), intent(in) :: e
    real(wp), parameter :: ce(5) = [0.0_wp, 0.1_wp, 0.5_wp, 1.2_wp, 2.0_wp], &
                           cs(5) = [1.6e6_wp, 1.65e6_wp, 2.2e6_wp, 4.0e6_wp, 9.0e6_wp]
    integer :: k
    k = 1
    do while (k < 4 .and. e > ce(k+1))
      k = k + 1
    end do
    curve_y = cs(k) + (cs(k+1) - cs(k))*(e - ce(k))/(ce(k+1) - ce(k))
  end function curve_y

  !> e with e + Y(e)/E = eps (uniaxial stress, compression eps > 0) by bisection.
  real(wp) function uniaxial_closed(eps, tabulated) result(ep)
    real(wp), intent(in) :: eps
    logical, intent(in) :: tabulated
    real(wp) :: lo, hi, y
    integer :: it
    lo = 0.0_wp
    hi = eps
    ep = 0.0_wp
    y = merge(curve_y(0.0_wp), y_law(0.0_wp), tabulated)
    if (eps <= y/E) return
    do it = 1, 200
      ep = 0.5_wp*(lo + hi)
      y = merge(curve_y(ep), y_law(ep), tabulated)
      if (ep + y/E > eps) then
        hi = ep
      else
        lo = ep
      end if
    end do
  end function uniaxial_closed

  !> The law continues past eps_d finite and increasing; a step past it converges.
  subroutine test_beyond_eps_d()
    type(material_t) :: mat
    real(wp) :: y1, y2, y3, dy, sig(4), eqps, dwp, L(2,2), F(2,2)
    integer :: stat
    call begin_test('foam: the law beyond eps_d')
    mat = foam(0.0_wp)
    call foam_yield(mat%foam, 0.9_wp*ed, y1, dy)
    call check_close(y1, y_law(0.9_wp*ed), 'Y(0.9 eps_d) is the law', rtol=1.0e-13_wp)
    call foam_yield(mat%foam, ed, y2, dy)
    call foam_yield(mat%foam, 1.5_wp*ed, y3, dy)
    call check(y2 > y1 .and. y3 > y2 .and. y3 < 1.0e20_wp .and. dy > 0.0_wp, &
      'finite and increasing at and beyond eps_d')
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    L = reshape([0.0_wp, 0.0_wp, 0.0_wp, -0.5_wp], [2, 2])
    sig = 0.0_wp
    eqps = 0.98_wp*ed
    call material_stress_update(mat, PLANE_STRAIN, L, 1.0_wp, F, sig, eqps, dwp, stat)
    call check(stat == MATERIAL_OK .and. eqps > 0.98_wp*ed, 'a large step near eps_d converges')
  end subroutine test_beyond_eps_d
end program test_foam
