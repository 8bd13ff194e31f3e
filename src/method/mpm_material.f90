!> Constitutive models: hypoelastic (Jaumann rate), J2 plasticity (radial return) with a linear
!! or Johnson-Cook flow stress, the crushable foam of Deshpande & Fleck (mpm_foam), Neo-Hookean.
! SPDX-License-Identifier: MIT
!
! Stress storage: sig(4) = (xx, yy, xy, zz), Cauchy stress [Pa]; sig(3) is the tensor
! component sigma_xy. Plane stress keeps sig(4) = 0 exactly; plane strain carries sigma_zz.
! Strain increments from D = sym(L) are tensor components (de_xy = (L12 + L21)/2 dt).
! On stat /= 0, sig and eqps are returned unchanged and dwp = 0. See docs/method.md.
module mpm_material
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
  use mpm_kinds, only: wp
  use mpm_constants, only: name_len, max_table, MODEL_ELASTIC, MODEL_NEOHOOKEAN, MODEL_J2, &
                           MODEL_FOAM, RATE_NONE, RATE_COWPER_SYMONDS, PLANE_STRAIN, &
                           PLANE_STRESS, FLOW_LINEAR, FLOW_JOHNSON_COOK
  use mpm_foam, only: foam_law_t, foam_alpha, foam_return
  implicit none
  private
  public :: material_new, material_from, material_wave_speed, material_stress_update, &
            material_energy_density
  public :: MATERIAL_OK, MATERIAL_NOT_CONVERGED, MATERIAL_BAD_INPUT

  integer, parameter :: MATERIAL_OK = 0             !! stat: update done
  integer, parameter :: MATERIAL_NOT_CONVERGED = 1  !! stat: an iteration did not converge
  integer, parameter :: MATERIAL_BAD_INPUT = 2      !! stat: non-finite or invalid input/result

  real(wp), parameter :: return_tol = 1.0e-12_wp    ! relative bracket width, return mapping
  real(wp), parameter :: newton_step_tol = 1.0e-8_wp ! relative last Newton step, return mapping
  integer, parameter :: return_max_iter = 100
  real(wp), parameter :: stretch_tol = 1.0e-14_wp   ! absolute tolerance on ln(F_zz)
  integer, parameter :: stretch_max_iter = 100

  !> The parameters of a material as the input gives them: one component per variable of the
  !! &material group, with its default (the reader reads the group into this type; the table
  !! of mpm_config_table says what each accepts); the model reads them from material_t, which
  !! extends this type.
  type, public :: material_cfg_t
    character(len=name_len) :: name = ''           !! label used by &body
    character(len=name_len) :: model = 'j2'        !! elastic | neohookean | j2 | foam
    character(len=name_len) :: rate_law = 'none'   !! none | cowper_symonds
    integer :: model_id = 0, rate_law_id = 0       !! codes of mpm_constants
    real(wp) :: E = -1.0_wp                        !! Young's modulus [Pa]
    real(wp) :: nu = -1.0_wp                       !! Poisson's ratio [-]
    real(wp) :: rho = -1.0_wp                      !! density [kg/m^3]
    real(wp) :: sigma_y = -1.0_wp                  !! initial yield stress [Pa]
    real(wp) :: hardening = 0.0_wp                 !! linear isotropic hardening modulus [Pa]
    real(wp) :: voce_q = 0.0_wp                    !! Voce saturation stress [Pa]
    real(wp) :: voce_b = 10.0_wp                   !! Voce saturation rate [-]
    real(wp) :: cs_d = 40.4_wp                     !! Cowper-Symonds D [1/s]
    real(wp) :: cs_q = 5.0_wp                      !! Cowper-Symonds q [-]
    character(len=name_len) :: flow_stress = 'linear'  !! linear | johnson_cook
    integer :: flow_stress_id = FLOW_LINEAR        !! code of mpm_constants
    real(wp) :: jc_b = 0.0_wp                      !! Johnson-Cook B [Pa] (A is sigma_y)
    real(wp) :: jc_n = 1.0_wp                      !! Johnson-Cook n [-]
    real(wp) :: jc_c = 0.0_wp                      !! Johnson-Cook C [-]
    real(wp) :: jc_rate0 = 1.0_wp                  !! Johnson-Cook reference strain rate [1/s]
    real(wp) :: sigma_p = -1.0_wp                  !! foam: plateau stress [Pa]
    real(wp) :: nu_plastic = 0.0_wp                !! foam: plastic Poisson's ratio [-]
    real(wp) :: foam_alpha = -1.0_wp               !! foam: shape factor (> 0: not nu_plastic) [-]
    real(wp) :: foam_gamma = 0.0_wp                !! foam: linear hardening gamma [Pa]
    real(wp) :: foam_alpha2 = 0.0_wp               !! foam: densification alpha2 [Pa]
    real(wp) :: foam_beta = 1.0_wp                 !! foam: densification exponent beta [-]
    real(wp) :: eps_d = -1.0_wp                    !! foam: densification strain [-]
    integer :: n_curve = 0                         !! foam: points of the uniaxial curve (0: law)
    real(wp) :: curve_strain(max_table) = 0.0_wp   !! foam: its equivalent plastic strains [-]
    real(wp) :: curve_stress(max_table) = 0.0_wp   !! foam: its yield stresses [Pa]
  end type material_cfg_t

  !> A material: its parameters and the derived elastic constants.
  type, public, extends(material_cfg_t) :: material_t
    real(wp) :: lambda     !! first Lame constant [Pa]
    real(wp) :: mu         !! shear modulus [Pa]
    real(wp) :: bulk       !! bulk modulus [Pa]
    real(wp) :: alpha = 0.0_wp     !! foam: shape factor of the yield surface [-]
    type(foam_law_t) :: foam       !! foam: the hardening
  end type material_t

contains

  !> A material from its parameters, with the density scaled by mass_scale (quasi-static runs).
  !! Preconditions (checked by the input validation, not here): E > 0, -1 < nu < 0.5.
  pure function material_from(prm, mass_scale) result(mat)
    type(material_cfg_t), intent(in) :: prm   !! the parameters [-]
    real(wp), intent(in) :: mass_scale         !! density multiplier [-]
    type(material_t) :: mat
    mat%material_cfg_t = prm
    mat%rho = prm%rho*mass_scale
    mat%lambda = prm%E*prm%nu/((1.0_wp + prm%nu)*(1.0_wp - 2.0_wp*prm%nu))  ! Lame lambda
    mat%mu = prm%E/(2.0_wp*(1.0_wp + prm%nu))                       ! shear modulus
    mat%bulk = prm%E/(3.0_wp*(1.0_wp - 2.0_wp*prm%nu))              ! K = lambda + 2 mu / 3
    if (prm%model_id /= MODEL_FOAM) return
    mat%alpha = prm%foam_alpha
    if (.not. prm%foam_alpha > 0.0_wp) mat%alpha = foam_alpha(prm%nu_plastic)
    mat%foam = foam_law_t(sigma_p=prm%sigma_p, gamma=prm%foam_gamma, alpha2=prm%foam_alpha2, &
      beta=prm%foam_beta, eps_d=prm%eps_d, n_curve=prm%n_curve, &
      curve_strain=prm%curve_strain, curve_stress=prm%curve_stress)
  end function material_from

  !> material_from with the parameters as arguments (tests). The Johnson-Cook arguments
  !! (flow stress (sigma_y + jc_b eqps^jc_n)(1 + jc_c ln(rate / jc_rate0)) for model j2) are
  !! optional; without them the flow stress is linear.
  pure function material_new(model, rate_law, E, nu, rho, sigma_y, hardening, cs_d, cs_q, &
      flow, jc_b, jc_n, jc_c, jc_rate0) result(mat)
    integer, intent(in) :: model         !! MODEL_ELASTIC, MODEL_NEOHOOKEAN or MODEL_J2 [-]
    integer, intent(in) :: rate_law      !! RATE_NONE or RATE_COWPER_SYMONDS [-]
    real(wp), intent(in) :: E            !! Young's modulus [Pa]
    real(wp), intent(in) :: nu           !! Poisson's ratio [-]
    real(wp), intent(in) :: rho          !! reference density [kg/m^3]
    real(wp), intent(in) :: sigma_y      !! initial yield stress [Pa]
    real(wp), intent(in) :: hardening    !! linear isotropic plastic modulus H [Pa]
    real(wp), intent(in) :: cs_d         !! Cowper-Symonds D [1/s]
    real(wp), intent(in) :: cs_q         !! Cowper-Symonds q [-]
    integer, intent(in), optional :: flow       !! FLOW_LINEAR or FLOW_JOHNSON_COOK [-]
    real(wp), intent(in), optional :: jc_b      !! Johnson-Cook B [Pa]
    real(wp), intent(in), optional :: jc_n      !! Johnson-Cook n [-]
    real(wp), intent(in), optional :: jc_c      !! Johnson-Cook C [-]
    real(wp), intent(in), optional :: jc_rate0  !! Johnson-Cook reference rate [1/s]
    type(material_t) :: mat
    type(material_cfg_t) :: p
    p = material_cfg_t(model_id=model, rate_law_id=rate_law, E=E, nu=nu, rho=rho, &
                       sigma_y=sigma_y, hardening=hardening, cs_d=cs_d, cs_q=cs_q)
    if (present(flow)) p%flow_stress_id = flow
    if (present(jc_b)) p%jc_b = jc_b
    if (present(jc_n)) p%jc_n = jc_n
    if (present(jc_c)) p%jc_c = jc_c
    if (present(jc_rate0)) p%jc_rate0 = jc_rate0
    mat = material_from(p, 1.0_wp)
  end function material_new

  !> Dilatational wave speed sqrt((lambda + 2 mu) / rho) [m/s].
  pure function material_wave_speed(mat) result(c)
    type(material_t), intent(in) :: mat  !! material [-]
    real(wp) :: c
    c = sqrt((mat%lambda + 2.0_wp*mat%mu)/mat%rho)  ! c_d, docs/method.md (time step)
  end function material_wave_speed

  !> Update the Cauchy stress of one particle over one step.
  !! elastic/j2/foam: exact 2-D Jaumann rotation by W = skew(L), elastic increment from
  !! D = sym(L), then (j2, foam) the return to the yield surface; neohookean: stress from F, L and
  !! eqps ignored (foam: eqps is the work-conjugate strain of Deshpande & Fleck).
  !! stat: 0 ok, 1 return mapping or thickness iteration not converged, 2 non-finite or
  !! invalid input (or a non-finite result); on stat /= 0 sig and eqps are unchanged, dwp = 0.
  pure subroutine material_stress_update(mat, plane, L, dt, F, sig, eqps, dwp, stat, w)
    type(material_t), intent(in) :: mat   !! material [-]
    integer, intent(in) :: plane          !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: L(2,2)        !! velocity gradient, L(i,j) = dv_i/dx_j [1/s]
    real(wp), intent(in) :: dt            !! time step [s]
    real(wp), intent(in) :: F(2,2)        !! in-plane deformation gradient, end of step [-]
    real(wp), intent(inout) :: sig(4)     !! Cauchy stress (xx, yy, xy, zz) [Pa]
    real(wp), intent(inout) :: eqps       !! equivalent plastic strain [-]
    real(wp), intent(out) :: dwp          !! plastic dissipation per current volume [J/m^3]
    integer, intent(out) :: stat          !! 0 ok, 1 not converged, 2 bad input [-]
    !> stored elastic energy per current volume at the end of the step, as
    !! material_energy_density gives it (set when stat = 0) [J/m^3]
    real(wp), intent(out), optional :: w
    real(wp) :: s(4), deqps, dissipation, energy
    dwp = 0.0_wp
    deqps = 0.0_wp
    dissipation = 0.0_wp
    stat = MATERIAL_BAD_INPUT
    if (plane /= PLANE_STRAIN .and. plane /= PLANE_STRESS) return
    select case (mat%model_id)
    case (MODEL_NEOHOOKEAN)
      if (.not. all(ieee_is_finite(F))) return
      call neohookean_stress(mat, plane, F, s, energy, stat)
      if (stat /= MATERIAL_OK) return
    case (MODEL_ELASTIC, MODEL_J2, MODEL_FOAM)
      ! Check before any arithmetic: an ordered comparison with NaN would itself trap.
      if (.not. (all(ieee_is_finite(L)) .and. ieee_is_finite(dt) .and. &
                 all(ieee_is_finite(sig)) .and. ieee_is_finite(eqps))) return
      if (dt < 0.0_wp) return
      s = sig
      call rotate_jaumann(L, dt, s)
      call add_elastic_increment(mat, plane, L, dt, s)
      if (mat%model_id == MODEL_J2) then
        if (mat%flow_stress_id == FLOW_JOHNSON_COOK .or. mat%voce_q > 0.0_wp) then
          call flow_return(mat, plane, dt, eqps, s, deqps, dissipation, stat)
        else
          call j2_return(mat, plane, dt, eqps, s, deqps, dissipation, stat)
        end if
        if (stat /= MATERIAL_OK) return
      else if (mat%model_id == MODEL_FOAM) then
        call foam_return(plane, mat%E, mat%nu, mat%alpha, mat%foam, eqps, s, deqps, &
                         dissipation, stat)
        if (stat /= MATERIAL_OK) return
      end if
      if (present(w)) energy = linear_energy(mat, plane, s)
    case default
      return
    end select
    if (.not. (all(ieee_is_finite(s)) .and. ieee_is_finite(dissipation))) then
      stat = MATERIAL_BAD_INPUT   ! overflow from a huge but finite input
      return
    end if
    sig = s
    eqps = eqps + deqps
    dwp = dissipation
    if (present(w)) w = energy
    stat = MATERIAL_OK
  end subroutine material_stress_update

  !> Stored elastic energy per unit current volume [J/m^3].
  !! elastic/j2/foam: (1/2) sigma : C^-1 : sigma with the 3-D compliance (sigma_zz = 0 in plane
  !! stress, sig(4) in plane strain); neohookean: W(F) / J with J = det(F_2d) F_zz.
  !! Returns a quiet NaN for an inadmissible F (det F <= 0) or unknown model/plane.
  pure function material_energy_density(mat, plane, sig, F) result(w)
    type(material_t), intent(in) :: mat  !! material [-]
    integer, intent(in) :: plane         !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: sig(4)       !! Cauchy stress (xx, yy, xy, zz) [Pa]
    real(wp), intent(in) :: F(2,2)       !! in-plane deformation gradient [-]
    real(wp) :: w
    real(wp) :: s(4)
    integer :: stat
    w = ieee_value(w, ieee_quiet_nan)
    if (plane /= PLANE_STRAIN .and. plane /= PLANE_STRESS) return
    select case (mat%model_id)
    case (MODEL_ELASTIC, MODEL_J2, MODEL_FOAM)
      w = linear_energy(mat, plane, sig)
    case (MODEL_NEOHOOKEAN)
      if (.not. all(ieee_is_finite(F))) return
      call neohookean_stress(mat, plane, F, s, w, stat)
      if (stat /= MATERIAL_OK) w = ieee_value(w, ieee_quiet_nan)
    end select
  end function material_energy_density

  !> (1/2) sigma : C^-1 : sigma with the 3-D compliance (sigma_zz = 0 in plane stress).
  pure function linear_energy(mat, plane, sig) result(w)
    type(material_t), intent(in) :: mat  !! material [-]
    integer, intent(in) :: plane         !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: sig(4)       !! Cauchy stress (xx, yy, xy, zz) [Pa]
    real(wp) :: w
    real(wp) :: szz, tr, ss
    szz = sig(4)
    if (plane == PLANE_STRESS) szz = 0.0_wp
    tr = sig(1) + sig(2) + szz
    ss = sig(1)**2 + sig(2)**2 + szz**2 + 2.0_wp*sig(3)**2
    w = 0.5_wp*((1.0_wp + mat%nu)*ss - mat%nu*tr**2)/mat%E  ! eps = ((1+nu) sig - nu tr I)/E
  end function linear_energy

  ! ---------------------------------------------------------------------------------------
  ! Hypoelastic part

  !> Exact integration of the Jaumann spin term over the step: sigma <- Q sigma Q^T, Q the
  !! rotation by w dt, w = (L21 - L12)/2; sigma_zz is unchanged.
  pure subroutine rotate_jaumann(L, dt, s)
    real(wp), intent(in) :: L(2,2)    !! velocity gradient [1/s]
    real(wp), intent(in) :: dt        !! time step [s]
    real(wp), intent(inout) :: s(4)   !! stress (xx, yy, xy, zz) [Pa]
    real(wp) :: phi, c, sn, mean, half_diff, half_diff_new
    phi = (L(2,1) - L(1,2))*dt   ! twice the rotation angle w dt
    if (phi == 0.0_wp) return
    c = cos(phi)
    sn = sin(phi)
    mean = 0.5_wp*(s(1) + s(2))
    half_diff = 0.5_wp*(s(1) - s(2))
    ! Mohr-circle form of Q sigma Q^T: the deviatoric pair turns by 2 w dt
    half_diff_new = c*half_diff - sn*s(3)
    s(3) = sn*half_diff + c*s(3)
    s(1) = mean + half_diff_new
    s(2) = mean - half_diff_new
  end subroutine rotate_jaumann

  !> Add C : D dt. Plane strain: 3-D law with D_zz = 0; plane stress: reduced law, s_zz = 0.
  pure subroutine add_elastic_increment(mat, plane, L, dt, s)
    type(material_t), intent(in) :: mat  !! material [-]
    integer, intent(in) :: plane         !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: L(2,2)       !! velocity gradient [1/s]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp), intent(inout) :: s(4)      !! stress (xx, yy, xy, zz) [Pa]
    real(wp) :: dexx, deyy, dexy, tr, lam, two_mu
    dexx = L(1,1)*dt
    deyy = L(2,2)*dt
    dexy = 0.5_wp*(L(1,2) + L(2,1))*dt
    tr = dexx + deyy
    two_mu = 2.0_wp*mat%mu
    if (plane == PLANE_STRAIN) then
      lam = mat%lambda
      s(4) = s(4) + lam*tr                                  ! d sigma_zz = lambda tr(de)
    else
      lam = 2.0_wp*mat%lambda*mat%mu/(mat%lambda + two_mu)  ! plane-stress lambda = E nu/(1-nu^2)
      s(4) = 0.0_wp
    end if
    s(1) = s(1) + lam*tr + two_mu*dexx   ! d sigma = lambda tr(de) I + 2 mu de
    s(2) = s(2) + lam*tr + two_mu*deyy
    s(3) = s(3) + two_mu*dexy
  end subroutine add_elastic_increment

  ! ---------------------------------------------------------------------------------------
  ! J2 plasticity

  !> Return the trial stress s to the von Mises surface (linear isotropic hardening, optional
  !! Cowper-Symonds factor). Plane strain: 3-D radial return, closed form without rate effects.
  !! Plane stress: plane-stress-projected return (Simo & Taylor 1986) with a scalar Newton.
  pure subroutine j2_return(mat, plane, dt, eqps, s, deqps, dwp, stat)
    type(material_t), intent(in) :: mat  !! material [-]
    integer, intent(in) :: plane         !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp), intent(in) :: eqps         !! equivalent plastic strain at step start [-]
    real(wp), intent(inout) :: s(4)      !! trial stress in, returned stress out [Pa]
    real(wp), intent(out) :: deqps       !! equivalent plastic strain increment [-]
    real(wp), intent(out) :: dwp         !! plastic dissipation per current volume [J/m^3]
    integer, intent(out) :: stat         !! 0 ok, 1 not converged, 2 bad parameters [-]
    real(wp) :: k0, p, dev(4), q, three_mu, x, x_hi, fac, k_end, a, t1, t2, fa, fb
    logical :: rate
    deqps = 0.0_wp
    dwp = 0.0_wp
    stat = MATERIAL_BAD_INPUT
    rate = mat%rate_law_id == RATE_COWPER_SYMONDS
    if (.not. (mat%sigma_y > 0.0_wp .and. mat%hardening >= 0.0_wp)) return
    if (rate .and. .not. (mat%cs_d > 0.0_wp .and. mat%cs_q > 0.0_wp)) return
    stat = MATERIAL_OK
    three_mu = 3.0_wp*mat%mu
    k0 = mat%sigma_y + mat%hardening*eqps       ! static yield, yield = sigma_y + H eqps
    if (plane == PLANE_STRAIN) then
      call split_deviator(s, p, dev, q)
      if (q <= k0) return
      deqps = (q - k0)/(three_mu + mat%hardening)  ! radial return, Simo & Hughes (1998) ch. 3
      if (.not. rate) then
        fac = 1.0_wp - three_mu*deqps/q              ! n_{n+1} = n_trial, radial scaling
        k_end = k0 + mat%hardening*deqps
      else
        if (dt == 0.0_wp) then   ! infinite rate factor: no plastic flow in zero time
          deqps = 0.0_wp
          return
        end if
        x_hi = deqps/(k0 + mat%hardening*deqps)     ! static root in x = deqps / q_end
        x = 0.0_wp
        call solve_multiplier(mat, dt, k0, 0.0_wp, 0.0_wp, q*q, x_hi, rate, x, stat)
        if (stat /= MATERIAL_OK) return
        fac = 1.0_wp/(1.0_wp + three_mu*x)          ! s_end = s_trial / (1 + 3 mu x)
        deqps = x*q*fac
        k_end = (k0 + mat%hardening*deqps)*cs_factor(mat, deqps, dt)
      end if
      s = scaled_deviator(p, dev, fac)
    else
      call abc_split(s, fa, fb, t1, t2, q)
      if (q <= k0) return
      if (rate .and. dt == 0.0_wp) return
      a = mat%E/(2.0_wp*(1.0_wp - mat%nu))          ! plane-stress modulus of A: E / (2 (1 - nu))
      ! Bracket: q(x) <= q_trial / (1 + min(a, 3 mu) x) and yield >= k0; at x = 1/H, f <= -k0.
      x_hi = (q/k0 - 1.0_wp)/min(a, three_mu)
      if (mat%hardening > 0.0_wp) x_hi = min(x_hi, 1.0_wp/mat%hardening)
      x = 0.0_wp
      if (.not. rate) x = min((q - k0)/(q*mat%hardening + three_mu*k0), 0.5_wp*x_hi)
      call solve_multiplier(mat, dt, k0, a, t1, t2, x_hi, rate, x, stat)
      if (stat /= MATERIAL_OK) return
      fac = 1.0_wp/(1.0_wp + three_mu*x)     ! B, C = trial / (1 + 3 mu x)
      call abc_return(a, x, fac, fa, fb, s, deqps)
      k_end = k0 + mat%hardening*deqps
      if (rate) k_end = k_end*cs_factor(mat, deqps, dt)
    end if
    dwp = k_end*deqps    ! sigma_end : d eps_p = q_end deqps = yield_end deqps
  end subroutine j2_return

  !> Cowper-Symonds factor 1 + (deqps / (D dt))^(1/q) (Cowper & Symonds 1957; Jones 1989).
  pure function cs_factor(mat, deqps, dt) result(r)
    type(material_t), intent(in) :: mat  !! material [-]
    real(wp), intent(in) :: deqps        !! equivalent plastic strain increment [-]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp) :: r
    r = 1.0_wp
    if (deqps > 0.0_wp) r = 1.0_wp + (deqps/(mat%cs_d*dt))**(1.0_wp/mat%cs_q)
  end function cs_factor

  !> Safeguarded Newton-bisection for x = deqps / q_end on the bracket [0, x_hi].
  !! Unknown x: the returned equivalent stress is qbar(x) = sqrt(t1/(1+a x)^2 + t2/(1+3 mu x)^2)
  !! and deqps = x qbar(x). Static: g = qbar - (k0 + H deqps). Rate form (no infinite slope):
  !! g = D dt (r - 1)|r - 1|^(q-1) - deqps, r = qbar/(k0 + H deqps). Both decrease in x,
  !! g(0) > 0 and g(x_hi) <= 0. Stops on a Newton step < 1e-8 x or a bracket < 1e-12 x_hi.
  pure subroutine solve_multiplier(mat, dt, k0, a, t1, t2, x_hi, rate, x, stat)
    type(material_t), intent(in) :: mat  !! material [-]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp), intent(in) :: k0           !! static yield stress at step start [Pa]
    real(wp), intent(in) :: a            !! modulus of the first invariant part [Pa]
    real(wp), intent(in) :: t1           !! trial A^2 [Pa^2]
    real(wp), intent(in) :: t2           !! trial 3 (B^2 + C^2) [Pa^2]
    real(wp), intent(in) :: x_hi         !! upper bracket [1/Pa]
    logical, intent(in) :: rate          !! Cowper-Symonds on [-]
    real(wp), intent(inout) :: x         !! start value in [0, x_hi), root out [1/Pa]
    integer, intent(out) :: stat         !! 0 ok, 1 not converged [-]
    real(wp) :: lo, hi, xn, g, dg
    integer :: it
    stat = MATERIAL_OK
    lo = 0.0_wp
    hi = x_hi
    do it = 1, return_max_iter
      call multiplier_residual(mat, dt, k0, a, t1, t2, x, rate, g, dg)
      if (g > 0.0_wp) then
        lo = x
      else if (g < 0.0_wp) then
        hi = x
      else
        return
      end if
      xn = -1.0_wp
      if (dg < 0.0_wp) then
        xn = x - g/dg                          ! Newton
        if (abs(xn - x) <= newton_step_tol*x) then   ! quadratic: error of xn ~ (step/x)^2
          x = xn
          return
        end if
      end if
      if (.not. (xn > lo .and. xn < hi)) xn = 0.5_wp*(lo + hi)   ! bisection safeguard
      x = xn
      if (hi - lo <= return_tol*hi) return
    end do
    stat = MATERIAL_NOT_CONVERGED
  end subroutine solve_multiplier

  !> Residual g(x) and dg/dx of the return-mapping scalar equation (see solve_multiplier).
  pure subroutine multiplier_residual(mat, dt, k0, a, t1, t2, x, rate, g, dg)
    type(material_t), intent(in) :: mat  !! material [-]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp), intent(in) :: k0           !! static yield stress at step start [Pa]
    real(wp), intent(in) :: a            !! modulus of the first invariant part [Pa]
    real(wp), intent(in) :: t1           !! trial A^2 [Pa^2]
    real(wp), intent(in) :: t2           !! trial 3 (B^2 + C^2) [Pa^2]
    real(wp), intent(in) :: x            !! unknown x = deqps / q_end [1/Pa]
    logical, intent(in) :: rate          !! Cowper-Symonds on [-]
    real(wp), intent(out) :: g           !! residual [Pa] (static) or [-] (rate)
    real(wp), intent(out) :: dg          !! dg/dx [Pa^2] or [Pa]
    real(wp) :: ea, eb, b, qb, dqb, dl, ddl, ks, dks, r, dr, rm1, pw, ddt
    b = 3.0_wp*mat%mu
    ea = 1.0_wp/(1.0_wp + a*x)
    eb = 1.0_wp/(1.0_wp + b*x)
    qb = sqrt(t1*ea**2 + t2*eb**2)
    dqb = -(a*t1*ea**3 + b*t2*eb**3)/qb
    dl = x*qb
    ddl = qb + x*dqb
    ks = k0 + mat%hardening*dl
    dks = mat%hardening*ddl
    if (.not. rate) then
      g = qb - ks
      dg = dqb - dks
    else
      ddt = mat%cs_d*dt
      r = qb/ks
      dr = (dqb*ks - qb*dks)/ks**2
      ! (deqps / (D dt))^(1/q) = q_end / yield_static - 1, raised to the power q; continued
      ! as an odd function below r = 1 (no kink for q > 1, still decreasing in x)
      rm1 = r - 1.0_wp
      if (rm1 /= 0.0_wp) then
        pw = abs(rm1)**(mat%cs_q - 1.0_wp)
        g = ddt*pw*rm1 - dl
        dg = ddt*mat%cs_q*pw*dr - ddl
      else
        g = -dl
        dg = -ddl
      end if
    end if
  end subroutine multiplier_residual

  !> Plane stress: the trial stress s in (A, B, C) = ((sxx+syy)/2, (sxx-syy)/2, sxy), with
  !! q^2 = A^2 + 3 (B^2 + C^2) = t1 + t2 (j2_return and flow_return).
  pure subroutine abc_split(s, fa, fb, t1, t2, q)
    real(wp), intent(in) :: s(4)         !! trial stress [Pa]
    real(wp), intent(out) :: fa, fb      !! A, B [Pa]
    real(wp), intent(out) :: t1, t2      !! A^2, 3 (B^2 + C^2) [Pa^2]
    real(wp), intent(out) :: q           !! von Mises stress [Pa]
    fa = 0.5_wp*(s(1) + s(2))
    fb = 0.5_wp*(s(1) - s(2))
    t1 = fa**2
    t2 = 3.0_wp*(fb**2 + s(3)**2)
    q = sqrt(t1 + t2)
  end subroutine abc_split

  !> Plane stress: the returned stress at the multiplier x, A = A_trial / (1 + a x) and
  !! B, C = trial fac (Simo & Taylor 1986), and deqps = x q_end.
  pure subroutine abc_return(a, x, fac, fa, fb, s, deqps)
    real(wp), intent(in) :: a            !! modulus of A, E / (2 (1 - nu)) [Pa]
    real(wp), intent(in) :: x            !! multiplier deqps / q_end [1/Pa]
    real(wp), intent(in) :: fac          !! 1 / (1 + 3 mu x) [-]
    real(wp), intent(inout) :: fa, fb    !! trial A, B in, returned out [Pa]
    real(wp), intent(inout) :: s(4)      !! trial stress in (C = s(3)), returned out [Pa]
    real(wp), intent(out) :: deqps       !! equivalent plastic strain increment [-]
    fa = fa/(1.0_wp + a*x)
    fb = fb*fac
    s(3) = s(3)*fac
    s(1) = fa + fb
    s(2) = fa - fb
    s(4) = 0.0_wp
    deqps = x*sqrt(fa**2 + 3.0_wp*(fb**2 + s(3)**2))
  end subroutine abc_return

  !> Plane strain: the pressure p, the deviator dev (xx, yy, xy, zz) and q = sqrt(3 J2) of the
  !! stress s (xx, yy, xy, zz) [Pa].
  pure subroutine split_deviator(s, p, dev, q)
    real(wp), intent(in) :: s(4)         !! stress [Pa]
    real(wp), intent(out) :: p           !! pressure (mean stress) [Pa]
    real(wp), intent(out) :: dev(4)      !! deviator [Pa]
    real(wp), intent(out) :: q           !! von Mises stress sqrt(3 J2) [Pa]
    p = (s(1) + s(2) + s(4))/3.0_wp
    dev = [s(1) - p, s(2) - p, s(3), s(4) - p]
    q = sqrt(1.5_wp*(dev(1)**2 + dev(2)**2 + dev(4)**2 + 2.0_wp*dev(3)**2))
  end subroutine split_deviator

  !> Plane strain: the stress p + fac dev (the radial return's scaling of the deviator) [Pa].
  pure function scaled_deviator(p, dev, fac) result(s)
    real(wp), intent(in) :: p            !! pressure [Pa]
    real(wp), intent(in) :: dev(4)       !! deviator [Pa]
    real(wp), intent(in) :: fac          !! scaling of the deviator [-]
    real(wp) :: s(4)
    s(1) = p + fac*dev(1)
    s(2) = p + fac*dev(2)
    s(3) = fac*dev(3)
    s(4) = p + fac*dev(4)
  end function scaled_deviator

  ! ---------------------------------------------------------------------------------------
  ! J2 plasticity with a nonlinear flow stress (Johnson-Cook; Voce)

  !> Return the trial stress s to the von Mises surface of a nonlinear flow stress k(e, rate)
  !! (flow_stress: Johnson-Cook, or the linear law with a Voce term), e = eqps + deqps, rate =
  !! deqps / dt. One unknown for both planes,
  !! x = deqps / q_end (as the Cowper-Symonds return): plane strain is the plane-stress form
  !! with no first-invariant part (t1 = 0, t2 = q_trial^2).
  pure subroutine flow_return(mat, plane, dt, eqps, s, deqps, dwp, stat)
    type(material_t), intent(in) :: mat  !! material [-]
    integer, intent(in) :: plane         !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp), intent(in) :: eqps         !! equivalent plastic strain at step start [-]
    real(wp), intent(inout) :: s(4)      !! trial stress in, returned stress out [Pa]
    real(wp), intent(out) :: deqps       !! equivalent plastic strain increment [-]
    real(wp), intent(out) :: dwp         !! plastic dissipation per current volume [J/m^3]
    integer, intent(out) :: stat         !! 0 ok, 1 not converged, 2 bad parameters [-]
    real(wp) :: k0, dk, p, dev(4), q, a, t1, t2, x, x_hi, fa, fb, fac, k_end
    logical :: rated
    deqps = 0.0_wp
    dwp = 0.0_wp
    stat = MATERIAL_BAD_INPUT
    if (mat%flow_stress_id == FLOW_JOHNSON_COOK) then
      rated = mat%jc_c > 0.0_wp
      if (.not. (mat%sigma_y > 0.0_wp .and. mat%jc_b >= 0.0_wp .and. mat%jc_n > 0.0_wp .and. &
                 mat%jc_n <= 1.0_wp .and. mat%jc_c >= 0.0_wp .and. mat%jc_rate0 > 0.0_wp)) return
    else
      rated = mat%rate_law_id == RATE_COWPER_SYMONDS
      if (.not. (mat%sigma_y > 0.0_wp .and. mat%hardening >= 0.0_wp .and. mat%voce_q >= 0.0_wp &
                 .and. mat%voce_b > 0.0_wp)) return
      if (rated .and. .not. (mat%cs_d > 0.0_wp .and. mat%cs_q > 0.0_wp)) return
    end if
    stat = MATERIAL_OK
    call flow_stress(mat, eqps, 0.0_wp, dt, k0, dk)   ! static yield at step start
    if (plane == PLANE_STRAIN) then
      call split_deviator(s, p, dev, q)
      a = 0.0_wp
      t1 = 0.0_wp
      t2 = q*q
      x_hi = (q/k0 - 1.0_wp)/(3.0_wp*mat%mu)
    else
      call abc_split(s, fa, fb, t1, t2, q)
      a = mat%E/(2.0_wp*(1.0_wp - mat%nu))
      x_hi = (q/k0 - 1.0_wp)/min(a, 3.0_wp*mat%mu)
    end if
    if (q <= k0) return
    if (dt == 0.0_wp .and. rated) return   ! infinite rate: no flow in zero time
    ! at x_hi the returned q is at most k0 and k >= k0: the root is in (0, x_hi]
    call flow_solve(mat, dt, eqps, a, t1, t2, x_hi, x, stat)
    if (stat /= MATERIAL_OK) return
    fac = 1.0_wp/(1.0_wp + 3.0_wp*mat%mu*x)      ! deviatoric (B, C) part / (1 + 3 mu x)
    if (plane == PLANE_STRAIN) then
      deqps = x*q*fac
      s = scaled_deviator(p, dev, fac)
    else
      call abc_return(a, x, fac, fa, fb, s, deqps)
    end if
    call flow_stress(mat, eqps, deqps, dt, k_end, dk)
    dwp = k_end*deqps    ! sigma_end : d eps_p = q_end deqps = yield_end deqps
  end subroutine flow_return

  !> Flow stress k and dk/dd at e = eqps + d, d the increment over the step: Johnson-Cook
  !! (jc_flow), or the linear law with its Voce saturation term,
  !! k = (sigma_y + H e + Q (1 - exp(-b e))) r, r = 1 + (d / (D dt))^(1/q) with Cowper-Symonds
  !! (Voce 1948; Cowper & Symonds 1957), else r = 1.
  pure subroutine flow_stress(mat, eqps, d, dt, k, dk)
    type(material_t), intent(in) :: mat  !! material [-]
    real(wp), intent(in) :: eqps         !! equivalent plastic strain at step start [-]
    real(wp), intent(in) :: d            !! its increment over the step, >= 0 [-]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp), intent(out) :: k           !! flow stress [Pa]
    real(wp), intent(out) :: dk          !! dk/dd [Pa]
    real(wp) :: e, h, dh, r, dr, z, x
    if (mat%flow_stress_id == FLOW_JOHNSON_COOK) then
      call jc_flow(mat, eqps, d, dt, k, dk)
      return
    end if
    e = eqps + d
    h = mat%sigma_y + mat%hardening*e
    dh = mat%hardening
    if (mat%voce_q /= 0.0_wp) then            ! the saturation term (the return's hot loop)
      x = exp(-mat%voce_b*e)
      h = h + mat%voce_q*(1.0_wp - x)
      dh = dh + mat%voce_q*mat%voce_b*x
    end if
    r = 1.0_wp
    dr = 0.0_wp
    if (mat%rate_law_id == RATE_COWPER_SYMONDS .and. d > 0.0_wp) then
      z = (d/(mat%cs_d*dt))**(1.0_wp/mat%cs_q)
      r = 1.0_wp + z
      dr = z/(mat%cs_q*d)
    end if
    k = h*r
    dk = dh*r + h*dr
  end subroutine flow_stress

  !> Johnson-Cook flow stress k = (A + B e^n) r, r = 1 + C ln(max(d / (rate0 dt), 1)),
  !! e = eqps + d, and dk/dd (where e > 0 or n = 1; 0 at e = 0 with n < 1, where it is
  !! infinite: the solver never evaluates there).
  pure subroutine jc_flow(mat, eqps, d, dt, k, dk)
    type(material_t), intent(in) :: mat  !! material [-]
    real(wp), intent(in) :: eqps         !! equivalent plastic strain at step start [-]
    real(wp), intent(in) :: d            !! its increment over the step, >= 0 [-]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp), intent(out) :: k           !! flow stress [Pa]
    real(wp), intent(out) :: dk          !! dk/dd [Pa]
    real(wp) :: e, h, dh, r, dr
    e = eqps + d
    h = mat%sigma_y
    dh = 0.0_wp
    if (mat%jc_n == 1.0_wp) then
      h = h + mat%jc_b*e
      dh = mat%jc_b
    else if (e > 0.0_wp) then
      h = h + mat%jc_b*e**mat%jc_n
      dh = mat%jc_b*mat%jc_n*e**(mat%jc_n - 1.0_wp)
    end if
    r = 1.0_wp
    dr = 0.0_wp
    if (mat%jc_c > 0.0_wp .and. d > mat%jc_rate0*dt) then
      r = 1.0_wp + mat%jc_c*log(d/(mat%jc_rate0*dt))
      dr = mat%jc_c/d
    end if
    k = h*r
    dk = dh*r + h*dr
  end subroutine jc_flow

  !> Safeguarded Newton-bisection for x = deqps / q_end in (0, x_hi] on
  !! g(x) = qbar(x) - k(x qbar(x)), qbar(x) = sqrt(t1/(1+a x)^2 + t2/(1+3 mu x)^2); g decreases
  !! (qbar decreases, x qbar increases, k does not decrease), g(0) > 0 >= g(x_hi). Starts at
  !! x_hi (never at 0, where dk/dd may be infinite); stops as solve_multiplier does.
  pure subroutine flow_solve(mat, dt, eqps, a, t1, t2, x_hi, x, stat)
    type(material_t), intent(in) :: mat  !! material [-]
    real(wp), intent(in) :: dt           !! time step [s]
    real(wp), intent(in) :: eqps         !! equivalent plastic strain at step start [-]
    real(wp), intent(in) :: a            !! modulus of the first invariant part [Pa]
    real(wp), intent(in) :: t1           !! trial A^2 [Pa^2]
    real(wp), intent(in) :: t2           !! trial 3 (B^2 + C^2) [Pa^2]
    real(wp), intent(in) :: x_hi         !! upper bracket [1/Pa]
    real(wp), intent(out) :: x           !! root [1/Pa]
    integer, intent(out) :: stat         !! 0 ok, 1 not converged [-]
    real(wp) :: lo, hi, xn, g, dg, ea, eb, qb, dqb, k, dk
    integer :: it
    stat = MATERIAL_OK
    lo = 0.0_wp
    hi = x_hi
    x = x_hi
    do it = 1, return_max_iter
      ea = 1.0_wp/(1.0_wp + a*x)
      eb = 1.0_wp/(1.0_wp + 3.0_wp*mat%mu*x)
      qb = sqrt(t1*ea**2 + t2*eb**2)
      dqb = -(a*t1*ea**3 + 3.0_wp*mat%mu*t2*eb**3)/qb
      call flow_stress(mat, eqps, x*qb, dt, k, dk)
      g = qb - k
      dg = dqb - dk*(t1*ea**3 + t2*eb**3)/qb     ! d(x qbar)/dx = (t1 ea^3 + t2 eb^3)/qbar
      if (g > 0.0_wp) then
        lo = x
      else if (g < 0.0_wp) then
        hi = x
      else
        return
      end if
      xn = x - g/dg                              ! Newton (dg < 0)
      if (abs(xn - x) <= newton_step_tol*x) then
        x = xn
        return
      end if
      if (.not. (xn > lo .and. xn < hi)) xn = 0.5_wp*(lo + hi)   ! bisection safeguard
      x = xn
      if (hi - lo <= return_tol*hi) return
    end do
    stat = MATERIAL_NOT_CONVERGED
  end subroutine flow_solve

  ! ---------------------------------------------------------------------------------------
  ! Neo-Hookean

  !> Compressible Neo-Hookean stress sigma = (lambda ln J / J) I + (mu / J)(B - I) and the
  !! energy density W / J, W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2.
  !! Plane strain: F_zz = 1. Plane stress: F_zz from sigma_zz = 0 (Newton in ln F_zz).
  pure subroutine neohookean_stress(mat, plane, F, s, w, stat)
    type(material_t), intent(in) :: mat  !! material [-]
    integer, intent(in) :: plane         !! PLANE_STRAIN or PLANE_STRESS [-]
    real(wp), intent(in) :: F(2,2)       !! in-plane deformation gradient [-]
    real(wp), intent(out) :: s(4)        !! Cauchy stress (xx, yy, xy, zz) [Pa]
    real(wp), intent(out) :: w           !! energy per current volume [J/m^3]
    integer, intent(out) :: stat         !! 0 ok, 1 not converged, 2 det F <= 0 [-]
    real(wp) :: j2d, lnj, t, fzz, jac, b11, b22, b12, c, m
    s = 0.0_wp
    w = 0.0_wp
    stat = MATERIAL_BAD_INPUT
    j2d = F(1,1)*F(2,2) - F(1,2)*F(2,1)
    if (.not. (j2d > 0.0_wp)) return
    t = 0.0_wp
    if (plane == PLANE_STRESS) then
      call neohookean_thickness(mat, log(j2d), t, stat)
      if (stat /= MATERIAL_OK) return
    end if
    stat = MATERIAL_OK
    fzz = exp(t)
    lnj = log(j2d) + t
    jac = j2d*fzz
    b11 = F(1,1)**2 + F(1,2)**2                 ! B = F F^T
    b22 = F(2,1)**2 + F(2,2)**2
    b12 = F(1,1)*F(2,1) + F(1,2)*F(2,2)
    c = mat%lambda*lnj/jac
    m = mat%mu/jac
    s(1) = c + m*(b11 - 1.0_wp)                 ! docs/method.md, Neo-Hookean
    s(2) = c + m*(b22 - 1.0_wp)
    s(3) = m*b12
    if (plane == PLANE_STRAIN) s(4) = c         ! B_zz = 1
    w = (0.5_wp*mat%mu*(b11 + b22 + fzz**2 - 3.0_wp) - mat%mu*lnj &
         + 0.5_wp*mat%lambda*lnj**2)/jac        ! Simo & Hughes (1998), compressible Neo-Hookean
  end subroutine neohookean_stress

  !> Thickness log-stretch t = ln F_zz with sigma_zz = 0:
  !! h(t) = lambda (ln J_2d + t) + mu (exp(2 t) - 1) = 0. h is increasing and convex, the root
  !! lies between 0 and -ln J_2d; Newton from the linearised root, bisection as a safeguard.
  pure subroutine neohookean_thickness(mat, ln_j2d, t, stat)
    type(material_t), intent(in) :: mat  !! material [-]
    real(wp), intent(in) :: ln_j2d       !! ln det(F_2d) [-]
    real(wp), intent(out) :: t           !! ln F_zz [-]
    integer, intent(out) :: stat         !! 0 ok, 1 not converged [-]
    real(wp) :: lo, hi, h, dh, tn, e2t
    integer :: it
    stat = MATERIAL_OK
    lo = min(0.0_wp, -ln_j2d)
    hi = max(0.0_wp, -ln_j2d)
    t = -mat%lambda*ln_j2d/(mat%lambda + 2.0_wp*mat%mu)   ! small-strain root
    do it = 1, stretch_max_iter
      e2t = exp(2.0_wp*t)
      h = mat%lambda*(ln_j2d + t) + mat%mu*(e2t - 1.0_wp)
      dh = mat%lambda + 2.0_wp*mat%mu*e2t
      if (h > 0.0_wp) then
        hi = t
      else if (h < 0.0_wp) then
        lo = t
      else
        return
      end if
      tn = t - h/dh
      if (.not. (tn >= lo .and. tn <= hi)) tn = 0.5_wp*(lo + hi)
      if (abs(tn - t) <= stretch_tol) then
        t = tn
        return
      end if
      t = tn
    end do
    stat = MATERIAL_NOT_CONVERGED
  end subroutine neohookean_thickness
end module mpm_material
