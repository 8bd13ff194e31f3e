!> The isotropic crushable foam of Deshpande & Fleck (2000): its yield stress, the hardening
!! law or a tabulated uniaxial curve, and the return of a trial stress to the yield surface.
! SPDX-License-Identifier: MIT
!
! Pure routines on plain arguments (mpm_material calls them after its elastic predictor).
! Stress storage as in mpm_material: s(4) = (xx, yy, xy, zz) [Pa]; plane stress keeps
! s(4) = 0, plane strain carries sigma_zz. The stat codes are mpm_material's: 0 ok,
! 1 not converged, 2 invalid parameters. See docs/method.md, "Crushable foam".
module mpm_foam
  use mpm_kinds, only: wp
  use mpm_constants, only: max_table, PLANE_STRAIN, PLANE_STRESS
  implicit none
  private
  public :: foam_law_t, foam_alpha, foam_yield, foam_equivalent, foam_return

  integer, parameter :: FOAM_OK = 0, FOAM_NOT_CONVERGED = 1, FOAM_BAD_INPUT = 2
  real(wp), parameter :: return_tol = 1.0e-12_wp     ! relative bracket width
  real(wp), parameter :: newton_step_tol = 1.0e-8_wp ! relative last Newton step
  integer, parameter :: return_max_iter = 100
  !> the hardening law's log term is continued by its tangent beyond (e/eps_d)^beta = z_cap,
  !! where ln(1/(1 - z)) = 13.8: finite at and beyond eps_d, increasing, slope continuous
  real(wp), parameter :: z_cap = 1.0_wp - 1.0e-6_wp

  !> The uniaxial hardening of the foam: Y(e) = sigma_p + gamma e/eps_d
  !! + alpha2 ln(1/(1 - (e/eps_d)^beta)), or with n_curve > 0 the tabulated curve
  !! (linear between its points, continued by its last segment).
  type :: foam_law_t
    real(wp) :: sigma_p = 0.0_wp        !! plateau (initial yield) stress [Pa]
    real(wp) :: gamma = 0.0_wp          !! linear hardening coefficient [Pa]
    real(wp) :: alpha2 = 0.0_wp         !! densification coefficient [Pa]
    real(wp) :: beta = 1.0_wp           !! densification exponent [-]
    real(wp) :: eps_d = 1.0_wp          !! densification strain [-]
    integer :: n_curve = 0              !! points of the tabulated curve (0: the law)
    real(wp) :: curve_strain(max_table) = 0.0_wp  !! equivalent plastic strain, 0 first [-]
    real(wp) :: curve_stress(max_table) = 0.0_wp  !! yield stress there [Pa]
  end type foam_law_t

contains

  !> The shape factor alpha of the yield surface from the plastic Poisson's ratio nu_p,
  !! alpha^2 = 9 (1 - 2 nu_p) / (2 (1 + nu_p)) (Deshpande & Fleck 2000, eq. 2.7); -1 < nu_p < 0.5.
  pure real(wp) function foam_alpha(nu_p) result(alpha)
    real(wp), intent(in) :: nu_p         !! plastic Poisson's ratio [-]
    alpha = sqrt(4.5_wp*(1.0_wp - 2.0_wp*nu_p)/(1.0_wp + nu_p))
  end function foam_alpha

  !> The equivalent stress sigma_hat, sigma_hat^2 = (sigma_e^2 + alpha^2 sigma_m^2)
  !! / (1 + (alpha/3)^2) (Deshpande & Fleck 2000, eq. 2.2), of s (plane stress: s(4) taken 0).
  pure real(wp) function foam_equivalent(plane, alpha, s) result(q)
    integer, intent(in) :: plane         !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: alpha        !! shape factor [-]
    real(wp), intent(in) :: s(4)         !! stress (xx, yy, xy, zz) [Pa]
    real(wp) :: szz, sm, se2
    szz = s(4)
    if (plane == PLANE_STRESS) szz = 0.0_wp
    sm = (s(1) + s(2) + szz)/3.0_wp
    se2 = 0.5_wp*((s(1) - s(2))**2 + (s(2) - szz)**2 + (szz - s(1))**2) + 3.0_wp*s(3)**2
    q = sqrt((se2 + (alpha*sm)**2)/(1.0_wp + (alpha/3.0_wp)**2))
  end function foam_equivalent

  !> Yield stress Y and dY/de at the equivalent plastic strain e >= 0.
  pure subroutine foam_yield(law, e, y, dy)
    type(foam_law_t), intent(in) :: law  !! hardening [-]
    real(wp), intent(in) :: e            !! equivalent plastic strain [-]
    real(wp), intent(out) :: y           !! yield stress [Pa]
    real(wp), intent(out) :: dy          !! dY/de [Pa]
    real(wp) :: r, z, zc, e_cap, ycap
    integer :: k, n
    if (law%n_curve > 0) then
      n = law%n_curve
      dy = 0.0_wp
      y = law%curve_stress(n)
      if (n == 1) return
      k = n - 1                          ! the segment of e: the last one beyond the table
      do while (k > 1 .and. e < law%curve_strain(k))
        k = k - 1
      end do
      dy = (law%curve_stress(k+1) - law%curve_stress(k))/ &
           (law%curve_strain(k+1) - law%curve_strain(k))
      y = law%curve_stress(k) + dy*(e - law%curve_strain(k))
      return
    end if
    r = max(e, 0.0_wp)/law%eps_d
    z = 0.0_wp
    if (r > 0.0_wp) z = r**law%beta
    if (z <= z_cap) then
      ! Y = sigma_p + gamma e/eps_d + alpha2 ln(1/(1 - (e/eps_d)^beta)), Reyes et al. (2003)
      y = law%sigma_p + law%gamma*r - law%alpha2*log(1.0_wp - z)
      dy = law%gamma/law%eps_d
      if (r > 0.0_wp) then
        dy = dy + law%alpha2*law%beta*(z/r)/(law%eps_d*(1.0_wp - z))
      else if (law%beta == 1.0_wp) then
        dy = dy + law%alpha2/law%eps_d
      end if
    else
      zc = z_cap
      e_cap = law%eps_d*zc**(1.0_wp/law%beta)
      ycap = law%sigma_p + law%gamma*e_cap/law%eps_d - law%alpha2*log(1.0_wp - zc)
      dy = law%gamma/law%eps_d + law%alpha2*law%beta*zc/(e_cap*(1.0_wp - zc))
      y = ycap + dy*(e - e_cap)
    end if
  end subroutine foam_yield

  !> Return the trial stress s to the yield surface sigma_hat = Y(eqps + deqps), associated
  !! flow, backward Euler. With x = dlambda / (c sigma_hat_end), c = 1 + (alpha/3)^2, both
  !! planes take the form sigma_hat(x)^2 = t1 / (1 + a x)^2 + t2 / (1 + b x)^2 and
  !! deqps = c x sigma_hat(x) (the work-conjugate strain: sigma : deps_p = sigma_hat deqps):
  !! plane strain: the mean stress over 1 + alpha^2 K x, the deviator over 1 + 3 G x;
  !! plane stress (sigma_zz = 0): A = (sxx + syy)/2 over 1 + a_ps (1 + 4 alpha^2/9) x,
  !! a_ps = E / (2 (1 - nu)), B = (sxx - syy)/2 and sxy over 1 + 3 G x.
  !! stat: 0 ok, 1 not converged, 2 invalid parameters (s unchanged, deqps = dwp = 0).
  pure subroutine foam_return(plane, E, nu, alpha, law, eqps, s, deqps, dwp, stat)
    integer, intent(in) :: plane         !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: E            !! Young's modulus [Pa]
    real(wp), intent(in) :: nu           !! Poisson's ratio [-]
    real(wp), intent(in) :: alpha        !! shape factor of the yield surface [-]
    type(foam_law_t), intent(in) :: law  !! hardening [-]
    real(wp), intent(in) :: eqps         !! equivalent plastic strain at step start [-]
    real(wp), intent(inout) :: s(4)      !! trial stress in, returned stress out [Pa]
    real(wp), intent(out) :: deqps       !! equivalent plastic strain increment [-]
    real(wp), intent(out) :: dwp         !! plastic dissipation per current volume [J/m^3]
    integer, intent(out) :: stat         !! 0 ok, 1 not converged, 2 invalid parameters [-]
    real(wp) :: c, g, k, a, b, t1, t2, q, y0, dy, x, x_hi, sm, dev(4), fa, fb, ka, fac_a, &
                fac_b, y_end
    deqps = 0.0_wp
    dwp = 0.0_wp
    stat = FOAM_BAD_INPUT
    if (.not. (alpha > 0.0_wp .and. E > 0.0_wp .and. nu > -1.0_wp .and. nu < 0.5_wp)) return
    if (law%n_curve == 0 .and. .not. (law%sigma_p > 0.0_wp .and. law%gamma >= 0.0_wp .and. &
        law%alpha2 >= 0.0_wp .and. law%beta > 0.0_wp .and. law%eps_d > 0.0_wp)) return
    if (law%n_curve > 0 .and. .not. law%curve_stress(1) > 0.0_wp) return
    if (plane /= PLANE_STRAIN .and. plane /= PLANE_STRESS) return
    stat = FOAM_OK
    c = 1.0_wp + (alpha/3.0_wp)**2
    g = E/(2.0_wp*(1.0_wp + nu))
    k = E/(3.0_wp*(1.0_wp - 2.0_wp*nu))
    b = 3.0_wp*g
    dev = 0.0_wp                               ! set for plane strain only
    if (plane == PLANE_STRAIN) then
      sm = (s(1) + s(2) + s(4))/3.0_wp
      dev = [s(1) - sm, s(2) - sm, s(3), s(4) - sm]
      t1 = (alpha*sm)**2/c
      t2 = 1.5_wp*(dev(1)**2 + dev(2)**2 + dev(4)**2 + 2.0_wp*dev(3)**2)/c
      a = alpha**2*k
    else
      fa = 0.5_wp*(s(1) + s(2))
      fb = 0.5_wp*(s(1) - s(2))
      ka = 1.0_wp + 4.0_wp*alpha**2/9.0_wp     ! sigma_m = 2 A / 3 in plane stress
      t1 = ka*fa**2/c
      t2 = 3.0_wp*(fb**2 + s(3)**2)/c
      a = ka*E/(2.0_wp*(1.0_wp - nu))
    end if
    q = sqrt(t1 + t2)
    call foam_yield(law, eqps, y0, dy)
    if (q <= y0) return
    ! at x_hi the returned sigma_hat is at most q / (1 + min(a, b) x_hi) = y0 <= Y: a bracket
    x_hi = (q/y0 - 1.0_wp)/min(a, b)
    call foam_solve(law, eqps, c, a, b, t1, t2, x_hi, x, stat)
    if (stat /= FOAM_OK) return
    fac_a = 1.0_wp/(1.0_wp + a*x)
    fac_b = 1.0_wp/(1.0_wp + b*x)
    if (plane == PLANE_STRAIN) then
      sm = sm*fac_a
      s = [sm + fac_b*dev(1), sm + fac_b*dev(2), fac_b*dev(3), sm + fac_b*dev(4)]
    else
      fa = fa*fac_a
      fb = fb*fac_b
      s = [fa + fb, fa - fb, s(3)*fac_b, 0.0_wp]
    end if
    deqps = c*x*sqrt(t1*fac_a**2 + t2*fac_b**2)
    call foam_yield(law, eqps + deqps, y_end, dy)
    dwp = y_end*deqps                  ! sigma : deps_p = sigma_hat deqps = Y_end deqps
  end subroutine foam_return

  !> Safeguarded Newton-bisection for x in (0, x_hi] on g(x) = q(x) - Y(eqps + c x q(x)),
  !! q(x) = sqrt(t1/(1+a x)^2 + t2/(1+b x)^2); g decreases (q decreases, x q increases, Y does
  !! not decrease), g(0) > 0 >= g(x_hi). Starts at x_hi (never at 0, where dY/de may be
  !! infinite for beta < 1); stops on a Newton step < 1e-8 x or a bracket < 1e-12 x_hi.
  pure subroutine foam_solve(law, eqps, c, a, b, t1, t2, x_hi, x, stat)
    type(foam_law_t), intent(in) :: law  !! hardening [-]
    real(wp), intent(in) :: eqps         !! equivalent plastic strain at step start [-]
    real(wp), intent(in) :: c            !! 1 + (alpha/3)^2 [-]
    real(wp), intent(in) :: a, b         !! moduli of the two parts [Pa]
    real(wp), intent(in) :: t1, t2       !! trial squares of the two parts [Pa^2]
    real(wp), intent(in) :: x_hi         !! upper bracket [1/Pa]
    real(wp), intent(out) :: x           !! root [1/Pa]
    integer, intent(out) :: stat         !! 0 ok, 1 not converged [-]
    real(wp) :: lo, hi, xn, r, dr, ea, eb, q, dq, y, dy
    integer :: it
    stat = FOAM_OK
    lo = 0.0_wp
    hi = x_hi
    x = x_hi
    do it = 1, return_max_iter
      ea = 1.0_wp/(1.0_wp + a*x)
      eb = 1.0_wp/(1.0_wp + b*x)
      q = sqrt(t1*ea**2 + t2*eb**2)
      dq = -(a*t1*ea**3 + b*t2*eb**3)/q
      call foam_yield(law, eqps + c*x*q, y, dy)
      r = q - y
      dr = dq - dy*c*(t1*ea**3 + t2*eb**3)/q     ! d(x q)/dx = (t1 ea^3 + t2 eb^3) / q
      if (r > 0.0_wp) then
        lo = x
      else if (r < 0.0_wp) then
        hi = x
      else
        return
      end if
      xn = x - r/dr                               ! Newton (dr < 0)
      if (abs(xn - x) <= newton_step_tol*x) then
        x = xn
        return
      end if
      if (.not. (xn > lo .and. xn < hi)) xn = 0.5_wp*(lo + hi)   ! bisection safeguard
      x = xn
      if (hi - lo <= return_tol*hi) return
    end do
    stat = FOAM_NOT_CONVERGED
  end subroutine foam_solve
end module mpm_foam
