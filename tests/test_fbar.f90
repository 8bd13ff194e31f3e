!> volumetric = 'fbar' and 'fbarwall' (issue 17): the patch test (a homogeneous deformation is reproduced
!! exactly: the averaged volume change equals the particle's, F is unchanged and the stresses
!! equal the standard treatment's to round-off), and a nearly incompressible closed form that
!! the standard treatment locks on: a thick elastic cylinder under a radial body force; for
!! 'fbarwall' also the patch test on a ring and its fit through the wall (a mean stress linear
!! through the wall is kept, its column sums are kept, an alternating one is removed).
!!   usage: test_fbar [SCRATCH] [--nu=NU] [--h=H] [--nt=N] [--damping=C] [--t=T] [--basis=B]
!!          (experiments: one cylinder run of each treatment with these settings)
! SPDX-License-Identifier: MIT
!
! Cylinder (plane strain, r_inner a, r_outer b, free surfaces, body force rho g e_r, quarter
! model): with k = rho g / (lambda + 2 mu) the radial displacement is
!   u(r) = A r + B / r - k r^2 / 3,
! and sigma_rr(a) = sigma_rr(b) = 0 give, with c = k (3 lambda + 4 mu) / 3,
!   B = c (b - a) / (2 mu (1/a^2 - 1/b^2)),   A = (c a + 2 mu B / a^2) / (2 (lambda + mu)).
! As nu -> 1/2 it tends to the isochoric u = B / r with B = rho g (b - a) / (2 mu (1/a^2 -
! 1/b^2)): the cylinder can only deform by shear, which is what a locking discretisation cannot
! represent.
program test_fbar
  use mpm_kinds, only: wp
  use mpm_constants, only: BASIS_LINEAR, BASIS_CPDI2, basis_names, SCHEME_MUSL, SCHEME_USF, &
                           scheme_names, PLANE_STRAIN, MODEL_ELASTIC, MODEL_J2, SECTOR_QUARTER, &
                           VOLUMETRIC_STANDARD, VOLUMETRIC_FBAR, VOLUMETRIC_FBARWALL
  use mpm_config, only: config_t
  use mpm_scene_builder, only: scene_new, scene_add_material, scene_add_ring, scene_add_rect
  use mpm_solver, only: sim_t, solver_step
  use mpm_weights, only: weights_compute
  use mpm_deformation, only: deformation_update
  use mpm_fbar, only: fbar_force_stress
  use testing, only: begin_test, check, check_close, finish_tests
  use testing_sim, only: must_setup
  implicit none
  ! the cylinder
  real(wp), parameter :: a = 0.01_wp, b = 0.02_wp, E = 10.0e6_wp, rho = 1000.0_wp
  real(wp), parameter :: g0 = 500.0_wp        ! body acceleration [m/s^2]: u(a) / a about 1e-3
  character(len=256) :: arg
  real(wp) :: nu, h, damping, t_end, e_std, e_fbar, e_wall
  integer :: nt, k, basis
  logical :: experiment

  nu = 0.499_wp
  h = 2.0e-3_wp
  nt = 10
  damping = 6000.0_wp
  t_end = 4.0e-3_wp
  basis = BASIS_CPDI2
  experiment = .false.
  do k = 1, command_argument_count()
    call get_command_argument(k, arg)
    if (arg(1:2) /= '--') cycle
    experiment = .true.
    if (arg(1:5) == '--nu=') read(arg(6:), *) nu
    if (arg(1:4) == '--h=') read(arg(5:), *) h
    if (arg(1:5) == '--nt=') read(arg(6:), *) nt
    if (arg(1:10) == '--damping=') read(arg(11:), *) damping
    if (arg(1:4) == '--t=') read(arg(5:), *) t_end
    if (trim(arg) == '--basis=linear') basis = BASIS_LINEAR
  end do
  if (experiment) then
    e_std = cylinder_error(VOLUMETRIC_STANDARD)
    e_fbar = cylinder_error(VOLUMETRIC_FBAR)
    e_wall = cylinder_error(VOLUMETRIC_FBARWALL)
    print '(a,f8.4,a,f8.4,a,f8.4)', 'cylinder: standard error ', e_std, ', fbar error ', &
      e_fbar, ', fbarwall error ', e_wall
    call finish_tests('test_fbar')
  end if

  call test_patch(BASIS_LINEAR, 2, SCHEME_MUSL)
  call test_patch(BASIS_CPDI2, 1, SCHEME_MUSL)
  call test_patch(BASIS_CPDI2, 2, SCHEME_USF)
  call test_patch_ring(BASIS_CPDI2, SCHEME_MUSL)
  call test_patch_ring(BASIS_LINEAR, SCHEME_USF)
  call test_wall_fit()
  call test_self_adjoint(VOLUMETRIC_FBAR)
  call test_self_adjoint(VOLUMETRIC_FBARWALL)
  call test_wall_two_layers()
  call test_cylinder()
  call finish_tests('test_fbar')

contains

  !> Patch test: a J2 block (ppc x ppc particles per cell) under the affine grid velocity
  !! v = G x (stretch, shear and spin, tr G /= 0), 60 steps of step 6 of both treatments from
  !! the same state, far into the plastic range. Every particle's L is G, so the averaged volume
  !! change must equal the particle's (relative 1e-13: a few roundings of a weighted mean), F
  !! must be the same bit for bit (the treatment never touches it), and the stresses, plastic
  !! strains and the forces' stress must equal the standard ones to round-off (1e-11 of the
  !! largest stress).
  subroutine test_patch(bas, ppc, scheme)
    integer, intent(in) :: bas, ppc, scheme
    type(config_t) :: cfg
    type(sim_t) :: s1, s2
    real(wp) :: smax, djmax, dev
    character(len=8) :: tag
    write(tag, '(i0,a,i0)') ppc, 'x', ppc
    call begin_test('patch test, '//trim(basis_names(bas))//' '//trim(scheme_names(scheme))// &
                    ', '//trim(tag)//' particles per cell')
    cfg = scene_new('patch', 1.0_wp, 0.01_wp, bas, scheme, PLANE_STRAIN)
    call scene_add_material(cfg, 'm', MODEL_J2, 1.0e9_wp, 0.3_wp, 1000.0_wp, &
                            sigma_y=1.0e6_wp, hardening=1.0e7_wp)
    call scene_add_rect(cfg, [0.013_wp, -0.004_wp], [0.06_wp, 0.04_wp], 6*ppc, 4*ppc)
    call run_patch(cfg, VOLUMETRIC_STANDARD, s1)
    call run_patch(cfg, VOLUMETRIC_FBAR, s2)
    call check(s2%prm%volumetric == VOLUMETRIC_FBAR, 'the second run is fbar')
    djmax = maxval(abs(s2%wk%dj))
    call check(djmax > 0.0_wp, 'the volume changes')
    call check(maxval(abs(s2%wk%djbar - s2%wk%dj)) <= 1.0e-13_wp*djmax, &
               'averaged volume change = the particle''s (Jbar = J)')
    call check(all(s2%p%F == s1%p%F), 'F identical')
    call check(all(s2%p%vol == s1%p%vol), 'areas identical')
    call check(maxval(s1%p%eqps) > 10.0_wp*1.0e6_wp/1.0e9_wp, 'far into the plastic range')
    smax = maxval(abs(s1%p%stress))
    call check_close(reshape(s2%p%stress, [size(s2%p%stress)]), &
                     reshape(s1%p%stress, [size(s1%p%stress)]), &
                     'stresses = standard', atol=1.0e-11_wp*smax)
    call check_close(s2%p%eqps, s1%p%eqps, 'plastic strains = standard', &
                     atol=1.0e-11_wp*maxval(s1%p%eqps))
    call fbar_force_stress(s2%p, s2%g, s2%wk, VOLUMETRIC_FBAR)
    dev = maxval(abs(s2%wk%sforce - s2%p%stress))
    call check(dev <= 1.0e-11_wp*smax, 'the forces'' stress = the stress')
  end subroutine test_patch

  !> The patch test of 'fbarwall': a quarter ring (4 particles through the wall, 1 per cell)
  !! under the same affine velocity, the same checks as test_patch.
  subroutine test_patch_ring(bas, scheme)
    integer, intent(in) :: bas, scheme
    type(config_t) :: cfg
    type(sim_t) :: s1, s2
    real(wp) :: smax, djmax, dev
    call begin_test('patch test of fbarwall, quarter ring, '//trim(basis_names(bas))//' '// &
                    trim(scheme_names(scheme)))
    cfg = scene_new('patch_ring', 1.0_wp, 0.005_wp, bas, scheme, PLANE_STRAIN)
    call scene_add_material(cfg, 'm', MODEL_J2, 1.0e9_wp, 0.3_wp, 1000.0_wp, &
                            sigma_y=1.0e6_wp, hardening=1.0e7_wp)
    call scene_add_ring(cfg, [0.0_wp, 0.0_wp], 0.04_wp, 0.06_wp, 4, sector=SECTOR_QUARTER)
    call run_patch(cfg, VOLUMETRIC_STANDARD, s1)
    call run_patch(cfg, VOLUMETRIC_FBARWALL, s2)
    call check(s2%prm%volumetric == VOLUMETRIC_FBARWALL, 'the second run is fbarwall')
    djmax = maxval(abs(s2%wk%dj))
    call check(djmax > 0.0_wp, 'the volume changes')
    call check(maxval(abs(s2%wk%djbar - s2%wk%dj)) <= 1.0e-13_wp*djmax, &
               'fitted volume change = the particle''s (Jbar = J)')
    call check(all(s2%p%F == s1%p%F), 'F identical')
    call check(all(s2%p%vol == s1%p%vol), 'areas identical')
    call check(maxval(s1%p%eqps) > 10.0_wp*1.0e6_wp/1.0e9_wp, 'far into the plastic range')
    smax = maxval(abs(s1%p%stress))
    call check_close(reshape(s2%p%stress, [size(s2%p%stress)]), &
                     reshape(s1%p%stress, [size(s1%p%stress)]), &
                     'stresses = standard', atol=1.0e-11_wp*smax)
    call fbar_force_stress(s2%p, s2%g, s2%wk, VOLUMETRIC_FBARWALL)
    dev = maxval(abs(s2%wk%sforce - s2%p%stress))
    call check(dev <= 1.0e-11_wp*smax, 'the forces'' stress = the stress')
  end subroutine test_patch_ring

  !> The fit through the wall on a quarter ring of 5 particles through the wall (the layer of a
  !! particle from its radius): an in-plane mean stress linear in the layer is kept (1e-9), the
  !! V-weighted sum of the mean stress is kept (1e-12), and one that alternates from layer to
  !! layer (+-1 MPa) is reduced to under half (its line over the five layers is nearly flat,
  !! about the mean -0.2 MPa).
  subroutine test_wall_fit()
    type(sim_t) :: s
    real(wp) :: r, dev, lin, sum_q, sum_f, worst
    integer :: ip, layer, n
    call begin_test('fbarwall: the fit through the wall')
    call elastic_quarter_ring(5, VOLUMETRIC_FBARWALL, s)
    n = s%p%np
    ! linear in the layer: kept
    do ip = 1, n
      r = norm2(s%p%x(:, ip))
      layer = nint((r - 0.04_wp)/0.004_wp + 0.5_wp)
      lin = 3.0e6_wp*real(layer, wp)
      s%p%stress(:, ip) = [1.0e6_wp + lin, 2.0e6_wp + lin, 5.0e5_wp, 0.0_wp]
    end do
    call fbar_force_stress(s%p, s%g, s%wk, VOLUMETRIC_FBARWALL)
    lin = maxval(abs(s%p%stress(1:2, 1:n)))
    dev = maxval(abs(s%wk%sforce(:, 1:n) - s%p%stress(:, 1:n)))
    call check(dev <= 1.0e-9_wp*lin, 'a mean stress linear through the wall is kept')
    ! alternating from layer to layer (layer from the radius): reduced, sums kept
    do ip = 1, n
      r = norm2(s%p%x(:, ip))
      layer = nint((r - 0.04_wp)/0.004_wp + 0.5_wp)
      s%p%stress(:, ip) = 0.0_wp
      s%p%stress(1:2, ip) = merge(1.0e6_wp, -1.0e6_wp, mod(layer, 2) == 0)
    end do
    call fbar_force_stress(s%p, s%g, s%wk, VOLUMETRIC_FBARWALL)
    worst = maxval(abs(0.5_wp*(s%wk%sforce(1, 1:n) + s%wk%sforce(2, 1:n))))
    call check(worst <= 0.5e6_wp, 'an alternating mean stress is reduced to under half')
    sum_q = sum(s%p%vol(1:n)*0.5_wp*(s%p%stress(1, 1:n) + s%p%stress(2, 1:n)))
    sum_f = sum(s%p%vol(1:n)*0.5_wp*(s%wk%sforce(1, 1:n) + s%wk%sforce(2, 1:n)))
    call check(abs(sum_f - sum_q) <= 1.0e-12_wp*sum(s%p%vol(1:n))*1.0e6_wp, &
               'the V-weighted sum of the mean stress is kept')
  end subroutine test_wall_fit

  !> The average of either treatment is self-adjoint in the V-weighted inner product,
  !! sum_p V_p a_p bbar_p = sum_p V_p abar_p b_p, which is what makes the forces' averaged mean
  !! stress the work-conjugate of the averaged volume change (the energy balance,
  !! tests/test_fbar_energy.py): two unrelated mean-stress fields on a quarter ring of four
  !! particles through the wall, averaged through the step's weights ('fbar') or the line through
  !! the wall ('fbarwall'); equal to 1e-12 of sum V |a| |b|. Each average also changes the fields
  !! (by more than 1 % of their RMS), so the equality is not that of the identity.
  subroutine test_self_adjoint(mode)
    integer, intent(in) :: mode             !! VOLUMETRIC_FBAR or VOLUMETRIC_FBARWALL
    type(sim_t) :: s
    real(wp), allocatable :: fa(:), fb(:), abar(:), bbar(:)
    real(wp) :: lhs, rhs, scale
    integer :: ip, n, stat
    character(len=:), allocatable :: errmsg
    call begin_test('the average is self-adjoint, '//merge('fbar    ', 'fbarwall', &
                    mode == VOLUMETRIC_FBAR))
    call elastic_quarter_ring(4, mode, s)
    s%wk%par = .false.
    errmsg = ''
    call weights_compute(s%prm, s%state_t, s%g, s%wk, s%diag, stat, errmsg)
    call check(stat == 0, 'weights: '//errmsg)
    n = s%p%np
    allocate(fa(n), fb(n), abar(n), bbar(n))
    do ip = 1, n          ! two fields with no relation to the averages' structure
      fa(ip) = 1.0e6_wp*sin(1.7_wp*real(ip, wp)) + 3.0e5_wp
      fb(ip) = 2.0e6_wp*cos(0.37_wp*real(ip*ip, wp)) - 1.0e5_wp
    end do
    s%p%stress(:, 1:n) = 0.0_wp
    s%p%stress(1, 1:n) = fa
    s%p%stress(2, 1:n) = fa
    call fbar_force_stress(s%p, s%g, s%wk, mode)
    abar = 0.5_wp*(s%wk%sforce(1, 1:n) + s%wk%sforce(2, 1:n))
    s%p%stress(1, 1:n) = fb
    s%p%stress(2, 1:n) = fb
    call fbar_force_stress(s%p, s%g, s%wk, mode)
    bbar = 0.5_wp*(s%wk%sforce(1, 1:n) + s%wk%sforce(2, 1:n))
    lhs = sum(s%p%vol(1:n)*fa*bbar)
    rhs = sum(s%p%vol(1:n)*abar*fb)
    scale = sum(s%p%vol(1:n)*abs(fa)*abs(fb))
    call check(abs(lhs - rhs) <= 1.0e-12_wp*scale, 'sum V a bbar = sum V abar b')
    call check(norm2(abar - fa) > 1.0e-2_wp*norm2(fa) .and. &
               norm2(bbar - fb) > 1.0e-2_wp*norm2(fb), 'the average changes both fields')
  end subroutine test_self_adjoint

  !> 'fbarwall' through two layers (n_thick = 2): the least-squares line through two points
  !! passes through both, so any mean stress is returned unchanged (1e-12 of its largest value):
  !! the treatment is then the standard one (--check warns of it; the study's crush at h = t/2,
  !! n_thick = 2 gives the standard run's history to 1e-9).
  subroutine test_wall_two_layers()
    type(sim_t) :: s
    integer :: ip, n
    call begin_test('fbarwall through two layers is the identity')
    call elastic_quarter_ring(2, VOLUMETRIC_FBARWALL, s)
    n = s%p%np
    do ip = 1, n
      s%p%stress(:, ip) = [1.0e6_wp*sin(1.3_wp*real(ip, wp)), 2.0e5_wp*cos(0.7_wp*real(ip, wp)), &
                           3.0e5_wp, 0.0_wp]
    end do
    call fbar_force_stress(s%p, s%g, s%wk, VOLUMETRIC_FBARWALL)
    call check(maxval(abs(s%wk%sforce(:, 1:n) - s%p%stress(:, 1:n))) <= &
               1.0e-12_wp*maxval(abs(s%p%stress(:, 1:n))), 'any mean stress is kept')
  end subroutine test_wall_two_layers

  !> An elastic quarter ring (r 40/60 mm, h = 5 mm, CPDI2) of n_thick particles through the
  !! wall, with the volumetric treatment mode, set up in s.
  subroutine elastic_quarter_ring(n_thick, mode, s)
    integer, intent(in) :: n_thick          !! particles through the wall
    integer, intent(in) :: mode             !! VOLUMETRIC_* code
    type(sim_t), intent(out) :: s
    type(config_t) :: cfg
    cfg = scene_new('quarter_ring', 1.0_wp, 0.005_wp, BASIS_CPDI2, SCHEME_MUSL, PLANE_STRAIN)
    cfg%solver%volumetric_id = mode
    call scene_add_material(cfg, 'm', MODEL_ELASTIC, 1.0e9_wp, 0.3_wp, 1000.0_wp, &
                            sigma_y=1.0_wp)
    call scene_add_ring(cfg, [0.0_wp, 0.0_wp], 0.04_wp, 0.06_wp, n_thick, sector=SECTOR_QUARTER)
    call must_setup(cfg, s)
  end subroutine elastic_quarter_ring

  !> Set up the patch with a treatment and run 60 steps of step 6 under v = G x.
  subroutine run_patch(cfg_in, vol_id, s)
    type(config_t), intent(in) :: cfg_in
    integer, intent(in) :: vol_id
    type(sim_t), intent(out) :: s
    real(wp), parameter :: gv(2, 2) = reshape([0.3_wp, -0.1_wp, 0.2_wp, -0.5_wp], [2, 2])
    real(wp), parameter :: dt = 1.0e-3_wp
    type(config_t) :: cfg
    real(wp) :: x(2)
    integer :: n, step, stat
    character(len=:), allocatable :: errmsg
    cfg = cfg_in
    cfg%solver%volumetric_id = vol_id
    call must_setup(cfg, s)
    s%wk%par = .false.
    errmsg = ''
    call weights_compute(s%prm, s%state_t, s%g, s%wk, s%diag, stat, errmsg)
    call check(stat == 0, 'weights: '//errmsg)
    do n = 1, s%g%nn
      x = s%g%origin + s%g%h*[real(mod(n - 1, s%g%nx), wp), real((n - 1)/s%g%nx, wp)]
      s%g%vel(:, n) = matmul(gv, x)
    end do
    do step = 1, 60
      call deformation_update(s%prm, s%state_t, s%g, s%wk, dt, stat, errmsg)
      if (stat /= 0) exit
    end do
    call check(stat == 0, 'deformation_update: '//errmsg)
  end subroutine run_patch

  !> The thick cylinder at nu = 0.499, 2 particles per cell through the wall (5 cells): the
  !! standard treatment locks (radial displacement a fraction of the closed form's), fbar is
  !! within 5 % of it (RMS over the particles, relative to the RMS of the closed form).
  subroutine test_cylinder()
    call begin_test('thick cylinder under a radial body force, nu = 0.499 (locking)')
    e_std = cylinder_error(VOLUMETRIC_STANDARD)
    e_fbar = cylinder_error(VOLUMETRIC_FBAR)
    e_wall = cylinder_error(VOLUMETRIC_FBARWALL)
    print '(a,f8.4,a,f8.4,a,f8.4)', 'cylinder: RMS error of u_r, standard ', e_std, ', fbar ', &
      e_fbar, ', fbarwall ', e_wall
    call check(e_fbar < 0.05_wp, 'fbar within 5 % of the closed form')
    call check(e_std > 4.0_wp*e_fbar, 'the standard treatment locks (error > 4 x fbar''s)')
    call check(e_wall < 0.05_wp, 'fbarwall within 5 % of the closed form')
    call check(e_std > 4.0_wp*e_wall, 'the standard treatment locks (error > 4 x fbarwall''s)')
  end subroutine test_cylinder

  !> Closed-form radial displacement of the cylinder at radius r [m] (program header).
  pure real(wp) function u_exact(r) result(u)
    real(wp), intent(in) :: r
    real(wp) :: lam, mu, kk, c, bb, aa
    lam = E*nu/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
    mu = E/(2.0_wp*(1.0_wp + nu))
    kk = rho*g0/(lam + 2.0_wp*mu)
    c = kk*(3.0_wp*lam + 4.0_wp*mu)/3.0_wp
    bb = c*(b - a)/(2.0_wp*mu*(1.0_wp/a**2 - 1.0_wp/b**2))
    aa = (c*a + 2.0_wp*mu*bb/a**2)/(2.0_wp*(lam + mu))
    u = aa*r + bb/r - kk*r*r/3.0_wp
  end function u_exact

  !> Run the cylinder with a treatment: the body force rises smoothly over the first quarter of
  !! the run, mass-proportional damping settles it; the RMS over the particles of the radial
  !! displacement's error, relative to the RMS of the closed form.
  real(wp) function cylinder_error(vol_id) result(err)
    integer, intent(in) :: vol_id
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp), allocatable :: X0(:, :)
    real(wp) :: r, er(2), ramp, t_ramp, se, sx, ur
    integer :: ip, k, stat
    character(len=:), allocatable :: errmsg
    cfg = scene_new('cylinder', t_end, h, basis, SCHEME_MUSL, PLANE_STRAIN)
    cfg%solver%volumetric_id = vol_id
    cfg%solver%damping = damping
    cfg%run%cfl = 0.2_wp
    call scene_add_material(cfg, 'rubber', MODEL_ELASTIC, E, nu, rho, sigma_y=1.0_wp)
    call scene_add_ring(cfg, [0.0_wp, 0.0_wp], a, b, nt, sector=SECTOR_QUARTER)
    call must_setup(cfg, s)
    allocate(X0, source=s%p%x(:, 1:s%p%np))
    allocate(s%prm%bacc(2, s%p%np))
    t_ramp = 0.25_wp*t_end
    stat = 0
    errmsg = ''
    do k = 1, 10000000
      if (s%t >= s%prm%t_end) exit
      ramp = 1.0_wp
      if (s%t < t_ramp) ramp = sin(0.5_wp*acos(-1.0_wp)*s%t/t_ramp)**2
      do ip = 1, s%p%np
        s%prm%bacc(:, ip) = ramp*g0*X0(:, ip)/norm2(X0(:, ip))
      end do
      call solver_step(s, stat, errmsg)
      if (stat /= 0) exit
    end do
    call check(stat == 0, 'run: '//errmsg)
    se = 0.0_wp
    sx = 0.0_wp
    do ip = 1, s%p%np
      r = norm2(X0(:, ip))
      er = X0(:, ip)/r
      ur = dot_product(s%p%x(:, ip) - X0(:, ip), er)
      se = se + (ur - u_exact(r))**2
      sx = sx + u_exact(r)**2
    end do
    err = sqrt(se/sx)
  end function cylinder_error

end program test_fbar
