!> Tests of the Johnson-Cook flow stress of mpm_material (model j2, flow FLOW_JOHNSON_COOK)
!! against closed forms: the static curve in pure shear, the linear-hardening limit, the
!! steady flow stress at a constant plastic rate and its ratio across a rate jump, the
!! consistency condition after every return, and the parameter checks.
! SPDX-License-Identifier: MIT
!
! Pure shear (L = [[0, g/2], [g/2, 0]], no spin) keeps the deviator's direction in both plane
! strain and plane stress (sigma_xx = sigma_yy = sigma_zz = 0), so the radial return is exact:
! after any number of steps, q = sqrt(3) |sigma_xy| and eqps satisfy eps = q/(3 mu) + eqps,
! eps = gamma/sqrt(3) the total equivalent strain, and q = k(eqps, rate) with the flow stress
! k = (A + B eqps^n)(1 + C ln(max(rate/rate0, 1))), rate = deqps/dt of the step.
program test_johnson_cook
  use testing, only: begin_test, check, check_close, finish_tests
  use mpm_kinds, only: wp
  use mpm_strings, only: itoa, rtoa
  use mpm_constants, only: MODEL_J2, RATE_NONE, PLANE_STRAIN, PLANE_STRESS, FLOW_LINEAR, &
                           FLOW_JOHNSON_COOK
  use mpm_material, only: material_t, material_new, material_stress_update, MATERIAL_OK, &
                          MATERIAL_BAD_INPUT
  implicit none

  ! Steel-like elasticity; Johnson-Cook constants of the order of a 4340 steel (A, B, n, C)
  real(wp), parameter :: E = 210.0e9_wp, nu = 0.3_wp, rho = 7800.0_wp
  real(wp), parameter :: A = 310.0e6_wp, B = 426.0e6_wp, n_jc = 0.34_wp, C = 0.015_wp
  real(wp), parameter :: rate0 = 1.0_wp
  integer, parameter :: planes(2) = [PLANE_STRAIN, PLANE_STRESS]
  character(len=*), parameter :: plane_label(2) = ['plane strain', 'plane stress']

  call test_static_curve()
  call test_linear_limit()
  call test_rate_steady_and_jump()
  call test_consistency()
  call test_parameters()
  call finish_tests('test_johnson_cook')

contains

  !> A Johnson-Cook material (A = sigma_y).
  function jc_material(b_, n_, c_, r0_) result(mat)
    real(wp), intent(in) :: b_, n_, c_, r0_
    type(material_t) :: mat
    mat = material_new(MODEL_J2, RATE_NONE, E, nu, rho, A, 0.0_wp, 40.4_wp, 5.0_wp, &
                       flow=FLOW_JOHNSON_COOK, jc_b=b_, jc_n=n_, jc_c=c_, jc_rate0=r0_)
  end function jc_material

  !> The flow stress written out independently of the module.
  pure function flow(b_, n_, c_, r0_, eqps, rate) result(k)
    real(wp), intent(in) :: b_, n_, c_, r0_, eqps, rate
    real(wp) :: k
    k = (A + b_*eqps**n_)*(1.0_wp + c_*log(max(rate/r0_, 1.0_wp)))
  end function flow

  !> sqrt(3 J2) of (xx, yy, xy, zz).
  pure function von_mises(s) result(q)
    real(wp), intent(in) :: s(4)
    real(wp) :: q, p
    p = (s(1) + s(2) + s(4))/3.0_wp
    q = sqrt(1.5_wp*((s(1) - p)**2 + (s(2) - p)**2 + (s(4) - p)**2 + 2.0_wp*s(3)**2))
  end function von_mises

  !> n steps of pure shear at the total equivalent strain rate `rate` (gamma_dot = sqrt(3) rate).
  subroutine shear(mat, plane, rate, dt, nsteps, sig, eqps, dwp, ok)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: plane, nsteps
    real(wp), intent(in) :: rate, dt
    real(wp), intent(inout) :: sig(4), eqps
    real(wp), intent(out) :: dwp
    logical, intent(inout) :: ok
    real(wp) :: L(2,2), F(2,2)
    integer :: k, stat
    L = reshape([0.0_wp, 0.5_wp, 0.5_wp, 0.0_wp], [2, 2])*sqrt(3.0_wp)*rate
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    dwp = 0.0_wp
    do k = 1, nsteps
      call material_stress_update(mat, plane, L, dt, F, sig, eqps, dwp, stat)
      ok = ok .and. stat == MATERIAL_OK
    end do
  end subroutine shear

  !> Root q of q = A + B (eps - q/(3 mu))^n by bisection on [A, A + B eps^n] (C = 0).
  function static_q(mu, eps, b_, n_) result(q)
    real(wp), intent(in) :: mu, eps, b_, n_
    real(wp) :: q, lo, hi, ep
    integer :: it
    lo = A
    hi = A + b_*eps**n_
    do it = 1, 200
      q = 0.5_wp*(lo + hi)
      ep = max(eps - q/(3.0_wp*mu), 0.0_wp)
      if (q - (A + b_*ep**n_) > 0.0_wp) then
        hi = q
      else
        lo = q
      end if
    end do
    q = 0.5_wp*(lo + hi)
  end function static_q

  !> C = 0: the stress-strain curve in pure shear is the root of q = A + B (eps - q/(3 mu))^n
  !! at every strain (radial return exact for this path). Tolerance 1e-10 relative: the
  !! return's Newton stops on a step below 1e-8 x (quadratic, error ~1e-16 x).
  subroutine test_static_curve()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, dt, rate, eps, q
    logical :: ok
    integer :: ip, stage
    do ip = 1, 2
      call begin_test('Johnson-Cook static curve in pure shear, '//plane_label(ip))
      mat = jc_material(B, n_jc, 0.0_wp, rate0)
      sig = 0.0_wp
      eqps = 0.0_wp
      ok = .true.
      rate = 100.0_wp
      dt = 1.0e-6_wp            ! 1e-4 strain per step: first yield at step 15
      eps = 0.0_wp
      do stage = 1, 4
        call shear(mat, planes(ip), rate, dt, 500, sig, eqps, dwp, ok)
        eps = eps + 500*rate*dt
        q = static_q(mat%mu, eps, B, n_jc)
        call check_close(von_mises(sig), q, 'q = A + B eqps^n at eps = '//rtoa(eps), &
                         rtol=1.0e-10_wp)
        call check_close(eqps, eps - q/(3.0_wp*mat%mu), 'eqps = eps - q/(3 mu)', rtol=1.0e-9_wp)
      end do
      call check(ok, 'all updates stat = 0')
      call check(sig(1) == 0.0_wp .and. sig(2) == 0.0_wp .and. sig(4) == 0.0_wp, &
                 'pure shear stays pure shear')
    end do
  end subroutine test_static_curve

  !> n = 1, C = 0 is linear hardening with H = B: in pure shear q = (A + H eps)/(1 + H/(3 mu))
  !! (eliminate eqps from q = A + H eqps, eps = q/(3 mu) + eqps). Both the Johnson-Cook law and
  !! the linear law of model j2 must give it (1e-12 relative).
  subroutine test_linear_limit()
    type(material_t) :: mjc, mlin
    real(wp), parameter :: H = 2.0e9_wp
    real(wp) :: s_jc(4), s_lin(4), e_jc, e_lin, dwp, dt, rate, eps, q
    logical :: ok
    integer :: ip, stage
    do ip = 1, 2
      call begin_test('Johnson-Cook with n = 1, C = 0 is linear hardening, '//plane_label(ip))
      mjc = jc_material(H, 1.0_wp, 0.0_wp, rate0)
      mlin = material_new(MODEL_J2, RATE_NONE, E, nu, rho, A, H, 40.4_wp, 5.0_wp)
      call check(mlin%flow_stress_id == FLOW_LINEAR, 'material_new without flow: the linear law')
      s_jc = 0.0_wp
      s_lin = 0.0_wp
      e_jc = 0.0_wp
      e_lin = 0.0_wp
      ok = .true.
      rate = 1.0e3_wp
      dt = 2.0e-7_wp
      eps = 0.0_wp
      do stage = 1, 3
        call shear(mjc, planes(ip), rate, dt, 400, s_jc, e_jc, dwp, ok)
        call shear(mlin, planes(ip), rate, dt, 400, s_lin, e_lin, dwp, ok)
        eps = eps + 400*rate*dt
        q = (A + H*eps)/(1.0_wp + H/(3.0_wp*mjc%mu))
        call check_close(von_mises(s_jc), q, 'johnson_cook: q = (A + H eps)/(1 + H/(3 mu))', &
                         rtol=1.0e-12_wp)
        call check_close(von_mises(s_lin), q, 'linear: q = (A + H eps)/(1 + H/(3 mu))', &
                         rtol=1.0e-12_wp)
        call check_close(e_jc, (q - A)/H, 'johnson_cook: eqps = (q - A)/H', rtol=1.0e-10_wp)
      end do
      call check(ok, 'all updates stat = 0')
    end do
  end subroutine test_linear_limit

  !> B = 0: at a constant plastic rate the stress settles at A (1 + C ln(rate/rate0)) (A below
  !! rate0); a jump from rate r1 to r2 raises it by (1 + C ln(r2/rate0))/(1 + C ln(r1/rate0)),
  !! and each step dissipates k rate dt. Tolerance 1e-10 relative (steady after a few steps:
  !! the elastic transient decays geometrically).
  subroutine test_rate_steady_and_jump()
    type(material_t) :: mat
    real(wp), parameter :: c_big = 0.05_wp, r1 = 100.0_wp, r2 = 1.0e4_wp, r_low = 0.1_wp
    real(wp) :: sig(4), eqps, dwp, q1, q2, dt
    logical :: ok
    integer :: ip
    do ip = 1, 2
      call begin_test('Johnson-Cook rate effect at steady flow, '//plane_label(ip))
      mat = jc_material(0.0_wp, n_jc, c_big, rate0)
      ok = .true.
      sig = 0.0_wp
      eqps = 0.0_wp
      dt = 1.0e-4_wp/r_low                 ! 1e-4 strain per step at every rate
      call shear(mat, planes(ip), r_low, dt, 200, sig, eqps, dwp, ok)
      call check_close(von_mises(sig), A, 'below rate0: q = A (no softening)', rtol=1.0e-12_wp)
      sig = 0.0_wp
      eqps = 0.0_wp
      dt = 1.0e-4_wp/r1
      call shear(mat, planes(ip), r1, dt, 200, sig, eqps, dwp, ok)
      q1 = von_mises(sig)
      call check_close(q1, A*(1.0_wp + c_big*log(r1/rate0)), 'q = A (1 + C ln(r1/rate0))', &
                       rtol=1.0e-10_wp)
      call check_close(dwp, q1*r1*dt, 'dwp = q rate dt', rtol=1.0e-10_wp)
      dt = 1.0e-4_wp/r2
      call shear(mat, planes(ip), r2, dt, 200, sig, eqps, dwp, ok)
      q2 = von_mises(sig)
      call check_close(q2/q1, (1.0_wp + c_big*log(r2/rate0))/(1.0_wp + c_big*log(r1/rate0)), &
                       'rate jump: q2/q1 = (1 + C ln(r2/rate0))/(1 + C ln(r1/rate0))', &
                       rtol=1.0e-10_wp)
      call check(ok, 'all updates stat = 0')
    end do
  end subroutine test_rate_steady_and_jump

  !> Random plastic steps from random states (eqps = 0 included: the infinite hardening slope
  !! of n < 1 at first yield): after each return the stress lies on the surface of the flow
  !! stress at its end, |q - k(eqps + deqps, deqps/dt)| <= 1e-9 A; deqps > 0; plane strain:
  !! q = q_trial - 3 mu deqps (radial return); plane stress: sigma_zz = 0.
  subroutine test_consistency()
    type(material_t) :: mat
    real(wp) :: sig(4), s0(4), trial(4), eqps, e0, dwp, L(2,2), F(2,2), dt, u(7), de(3), worst
    real(wp) :: k_end, lam
    integer :: ip, it, stat, n_plastic
    logical :: ok_stat, ok_dir, ok_pos, ok_dwp
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    call seed_random()
    do ip = 1, 2
      call begin_test('Johnson-Cook consistency after random returns, '//plane_label(ip))
      mat = jc_material(B, 0.2_wp, 0.02_wp, rate0)
      worst = 0.0_wp
      n_plastic = 0
      ok_stat = .true.
      ok_dir = .true.
      ok_pos = .true.
      ok_dwp = .true.
      do it = 1, 400
        call random_number(u)
        s0 = (2.0_wp*u(1:4) - 1.0_wp)*300.0e6_wp
        if (planes(ip) == PLANE_STRESS) s0(4) = 0.0_wp
        e0 = 0.0_wp
        if (mod(it, 2) == 0) e0 = 0.3_wp*u(5)
        dt = 10.0_wp**(-8.0_wp + 4.0_wp*u(6))
        L = reshape([2.0_wp*u(1) - 1.0_wp, u(2) - 0.5_wp, u(2) - 0.5_wp, &
                     2.0_wp*u(3) - 1.0_wp], [2, 2])*(10.0_wp**(-4.0_wp + 3.0_wp*u(7)))/dt
        sig = s0
        eqps = e0
        call material_stress_update(mat, planes(ip), L, dt, F, sig, eqps, dwp, stat)
        ok_stat = ok_stat .and. stat == MATERIAL_OK
        if (stat /= MATERIAL_OK .or. eqps == e0) cycle
        n_plastic = n_plastic + 1
        ok_pos = ok_pos .and. eqps > e0
        k_end = flow(B, 0.2_wp, 0.02_wp, rate0, eqps, (eqps - e0)/dt)
        worst = max(worst, abs(von_mises(sig) - k_end)/A)
        ok_dwp = ok_dwp .and. abs(dwp - k_end*(eqps - e0)) <= 1.0e-9_wp*k_end*(eqps - e0)
        if (planes(ip) == PLANE_STRAIN) then
          de = [L(1,1), L(2,2), 0.5_wp*(L(1,2) + L(2,1))]*dt
          lam = mat%lambda
          trial = s0 + [lam*(de(1) + de(2)) + 2.0_wp*mat%mu*de(1), &
                        lam*(de(1) + de(2)) + 2.0_wp*mat%mu*de(2), 2.0_wp*mat%mu*de(3), &
                        lam*(de(1) + de(2))]
          ok_dir = ok_dir .and. abs(von_mises(trial) - 3.0_wp*mat%mu*(eqps - e0) - &
                                    von_mises(sig)) <= 1.0e-9_wp*von_mises(trial)
        else
          ok_dir = ok_dir .and. sig(4) == 0.0_wp
        end if
      end do
      call check(ok_stat, 'every update stat = 0')
      call check(n_plastic > 100, 'more than 100 of 400 steps plastic ('//itoa(n_plastic)// &
                 ')')
      call check(ok_pos, 'deqps > 0 on every plastic step')
      call check(worst <= 1.0e-9_wp, '|q - k(eqps, rate)| <= 1e-9 A (worst '// &
                 rtoa(worst)//')')
      call check(ok_dwp, 'dwp = k deqps')
      if (planes(ip) == PLANE_STRAIN) then
        call check(ok_dir, 'radial return: q = q_trial - 3 mu deqps')
      else
        call check(ok_dir, 'sigma_zz = 0')
      end if
    end do
  end subroutine test_consistency

  !> Invalid parameters give MATERIAL_BAD_INPUT and leave the state alone; dt = 0 with C > 0
  !! (an infinite rate) gives no plastic flow.
  subroutine test_parameters()
    type(material_t) :: mat
    real(wp) :: sig(4), eqps, dwp, L(2,2), F(2,2)
    integer :: stat, k
    real(wp), parameter :: bad(4, 5) = reshape([ &
      -1.0_wp, 0.3_wp, 0.0_wp, 1.0_wp, &     ! B < 0
      B, 0.0_wp, 0.0_wp, 1.0_wp, &           ! n = 0
      B, 1.5_wp, 0.0_wp, 1.0_wp, &           ! n > 1
      B, 0.3_wp, -0.1_wp, 1.0_wp, &          ! C < 0
      B, 0.3_wp, C, 0.0_wp], [4, 5])         ! rate0 = 0
    call begin_test('Johnson-Cook parameter checks')
    F = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
    L = reshape([1.0e3_wp, 0.0_wp, 0.0_wp, -1.0e3_wp], [2, 2])
    do k = 1, size(bad, 2)
      mat = jc_material(bad(1, k), bad(2, k), bad(3, k), bad(4, k))
      sig = [400.0e6_wp, 0.0_wp, 0.0_wp, 0.0_wp]
      eqps = 0.0_wp
      call material_stress_update(mat, PLANE_STRAIN, L, 1.0e-5_wp, F, sig, eqps, dwp, stat)
      call check(stat == MATERIAL_BAD_INPUT .and. sig(1) == 400.0e6_wp .and. eqps == 0.0_wp, &
                 'bad parameter set '//itoa(k)//': stat = 2, state unchanged')
    end do
    mat = material_new(MODEL_J2, RATE_NONE, E, nu, rho, 0.0_wp, 0.0_wp, 40.4_wp, 5.0_wp, &
                       flow=FLOW_JOHNSON_COOK, jc_b=B, jc_n=n_jc, jc_c=C, jc_rate0=rate0)
    sig = [400.0e6_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    call material_stress_update(mat, PLANE_STRAIN, L, 1.0e-5_wp, F, sig, eqps, dwp, stat)
    call check(stat == MATERIAL_BAD_INPUT, 'A = sigma_y = 0: stat = 2')
    mat = jc_material(B, n_jc, C, rate0)
    sig = [400.0e6_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    call material_stress_update(mat, PLANE_STRAIN, L, 0.0_wp, F, sig, eqps, dwp, stat)
    call check(stat == MATERIAL_OK .and. eqps == 0.0_wp .and. dwp == 0.0_wp, &
               'dt = 0 with C > 0: no plastic flow')
  end subroutine test_parameters

  subroutine seed_random()
    integer :: n, i
    integer, allocatable :: seed(:)
    call random_seed(size=n)
    allocate(seed(n))
    seed = [(7907 + 104729*i, i = 1, n)]
    call random_seed(put=seed)
  end subroutine seed_random
end program test_johnson_cook
