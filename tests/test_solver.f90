!> Solver tests against conservation laws and closed forms (issue 3):
!! P2G/G2P conservation, free translation, elastic bar on a rigid target, colliding rings.
! SPDX-License-Identifier: MIT
program test_solver
  !$ use omp_lib, only: omp_set_num_threads
  use mpm_kinds, only: wp
  use mpm_constants, only: BASIS_LINEAR, BASIS_CPDI2, basis_names, &
                           SCHEME_USL, SCHEME_MUSL, scheme_names, PLANE_STRESS, &
                           PLANE_STRAIN, MODEL_ELASTIC, CONTACT_FRICTIONLESS
  use mpm_config, only: config_t, config_resolve
  use mpm_scene_builder, only: scene_new, scene_add_material, scene_add_rect, scene_add_ring
  use mpm_setup, only: setup_sim
  use mpm_solver, only: sim_t, solver_step
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  integer :: ib, is

  call test_transfer_conservation()
  do ib = BASIS_LINEAR, BASIS_CPDI2
    do is = SCHEME_USL, SCHEME_MUSL
      call test_free_translation(ib, is)
    end do
  end do
  do ib = BASIS_LINEAR, BASIS_CPDI2
    call test_bar_impact(ib)
  end do
  call test_ring_collision()
  call finish_tests('test_solver')

contains

  !> A one-material case: elastic, E, nu, rho; no bodies or walls yet (mpm_scene_builder).
  function base_case(E, nu, rho, h, t_end, basis, scheme, plane) result(cfg)
    real(wp), intent(in) :: E, nu, rho, h, t_end
    integer, intent(in) :: basis, scheme, plane
    type(config_t) :: cfg
    cfg = scene_new('test', t_end, h, basis, scheme, plane)
    call scene_add_material(cfg, 'm', MODEL_ELASTIC, E, nu, rho, sigma_y=1.0_wp)
  end function base_case

  subroutine add_rect(cfg, center, size, nx, ny, velocity)
    type(config_t), intent(inout) :: cfg
    real(wp), intent(in) :: center(2), size(2), velocity(2)
    integer, intent(in) :: nx, ny
    call scene_add_rect(cfg, center, size, nx, ny, velocity)
  end subroutine add_rect

  subroutine add_ring(cfg, center, r_inner, r_outer, n_thick, velocity)
    type(config_t), intent(inout) :: cfg
    real(wp), intent(in) :: center(2), r_inner, r_outer, velocity(2)
    integer, intent(in) :: n_thick
    call scene_add_ring(cfg, center, r_inner, r_outer, n_thick, velocity)
  end subroutine add_ring

  !> Validate the case as an input file would be (config_resolve), then set it up.
  subroutine must_setup(cfg_in, s)
    type(config_t), intent(in) :: cfg_in
    type(sim_t), intent(out) :: s
    type(config_t) :: cfg
    integer :: stat
    character(len=:), allocatable :: errmsg
    cfg = cfg_in
    call config_resolve(cfg, stat, errmsg)
    call check(stat == 0, 'config_resolve: '//errmsg)
    if (stat /= 0) error stop 1
    call setup_sim(cfg, s, stat, errmsg)
    call check(stat == 0, 'setup_sim: '//errmsg)
    if (stat /= 0) error stop 1
  end subroutine must_setup

  function momentum(s) result(pm)
    type(sim_t), intent(in) :: s
    real(wp) :: pm(2)
    integer :: ip
    pm = 0.0_wp
    do ip = 1, s%p%np
      pm = pm + s%p%mass(ip)*s%p%v(:, ip)
    end do
  end function momentum

  !> One step with a random velocity field and zero stress: P2G conserves mass and momentum
  !! exactly (partition of unity) with 1 and 2 threads, for every basis.
  subroutine test_transfer_conservation()
    type(config_t) :: cfg
    type(sim_t) :: s
    integer :: b, nthreads, stat
    real(wp) :: m0, p0(2), r(2)
    character(len=:), allocatable :: errmsg
    integer :: ip
    do b = BASIS_LINEAR, BASIS_CPDI2
      do nthreads = 1, 2
        !$ call omp_set_num_threads(nthreads)
        call begin_test('P2G/G2P conservation, '//trim(basis_names(b))//', threads '// &
                        achar(48 + nthreads))
        cfg = base_case(1.0e3_wp, 0.3_wp, 1.0_wp, 0.1_wp, 1.0_wp, b, SCHEME_MUSL, PLANE_STRAIN)
        call add_ring(cfg, [0.03_wp, -0.02_wp], 0.75_wp, 1.25_wp, 6, [0.0_wp, 0.0_wp])
        call must_setup(cfg, s)
        call random_seed(put=[(12345 + ip, ip = 1, 64)])
        do ip = 1, s%p%np
          call random_number(r)
          s%p%v(:, ip) = r - 0.5_wp
        end do
        s%prm%dt_fixed = 1.0e-12_wp              ! a step too short to deform anything measurably
        m0 = sum(s%p%mass)
        p0 = momentum(s)
        call solver_step(s, stat, errmsg)
        call check(stat == 0, 'step ok')
        call check_close(sum(s%g%mass), m0, 'grid mass = particle mass', rtol=1.0e-13_wp)
        call check_close(sum(s%g%mom, dim=2), p0, 'grid momentum (MUSL re-map) = particle '// &
                         'momentum', atol=1.0e-13_wp*m0)
        call check_close(momentum(s), p0, 'particle momentum after G2P', atol=1.0e-11_wp*m0)
      end do
    end do
    !$ call omp_set_num_threads(2)
  end subroutine test_transfer_conservation

  !> A body translating freely keeps zero stress and constant momentum.
  subroutine test_free_translation(b, scheme)
    integer, intent(in) :: b, scheme
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: p0(2), v(2)
    integer :: stat, k
    character(len=:), allocatable :: errmsg
    call begin_test('free translation, '//trim(basis_names(b))//' '//trim(scheme_names(scheme)))
    v = [3.0_wp, -2.0_wp]
    cfg = base_case(1.0e3_wp, 0.3_wp, 1.0_wp, 0.1_wp, 0.02_wp, b, scheme, PLANE_STRAIN)
    call add_ring(cfg, [0.0_wp, 0.0_wp], 0.75_wp, 1.25_wp, 4, v)
    call must_setup(cfg, s)
    p0 = momentum(s)
    do k = 1, 100000
      if (s%t >= s%prm%t_end) exit
      call solver_step(s, stat, errmsg)
      if (stat /= 0) exit
    end do
    call check(stat == 0, 'run ok: '//errmsg)
    call check(maxval(abs(s%p%stress)) < 1.0e-9_wp*cfg%materials(1)%E, 'stress stays zero')
    call check_close(momentum(s), p0, 'momentum constant', rtol=1.0e-12_wp)
    call check_close(s%p%x(:, 1) - s%p%x(:, 1), [0.0_wp, 0.0_wp], 'finite positions')
    call check_close(s%p%v(1, s%p%np), v(1), 'velocity unchanged', rtol=1.0e-12_wp)
  end subroutine test_free_translation

  !> Slender elastic bar on a rigid frictionless target (METHOD.md sec. 9): contact lasts
  !! 2 L / c and the bar leaves with its impact speed, c = sqrt(E / rho) (plane stress).
  !! L / h = 160: the rebound deficit is first order in h (4.2, 2.5, 1.3 % at L/h = 80, 160,
  !! 320 with CPDI2), the smeared unloading front leaving the bar end briefly in tension.
  subroutine test_bar_impact(b)
    integer, intent(in) :: b
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp), parameter :: E = 100.0_wp, rho = 1.0_wp, L = 1.0_wp, V = 0.01_wp
    real(wp), parameter :: gap0 = 0.002_wp, h = L/160.0_wp
    real(wp) :: c, t_first, t_end_contact, vrebound, pm(2), dt_contact
    integer :: stat, k
    logical :: in_contact
    character(len=:), allocatable :: errmsg
    call begin_test('elastic bar on a rigid target, '//trim(basis_names(b)))
    c = sqrt(E/rho)
    cfg = base_case(E, 0.3_wp, rho, h, gap0/V + 2.0_wp*L/c + 0.03_wp, b, SCHEME_MUSL, &
                    PLANE_STRESS)
    call add_rect(cfg, [gap0 + 0.5_wp*L, 0.0_wp], [L, 2.0_wp*h], 320, 4, [-V, 0.0_wp])
    deallocate(cfg%walls)
    allocate(cfg%walls(1))
    cfg%walls(1)%point = [0.0_wp, 0.0_wp]
    cfg%walls(1)%normal = [1.0_wp, 0.0_wp]
    cfg%walls(1)%contact_id = CONTACT_FRICTIONLESS
    call must_setup(cfg, s)
    t_first = -1.0_wp
    t_end_contact = -1.0_wp
    dt_contact = 0.0_wp
    in_contact = .false.
    do k = 1, 1000000
      if (s%t >= s%prm%t_end) exit
      call solver_step(s, stat, errmsg)
      if (stat /= 0) exit
      if (abs(s%walls(1)%force(1)) > 0.0_wp .and. t_first < 0.0_wp) then
        t_first = s%t - s%dt
        dt_contact = s%dt
        in_contact = .true.
      end if
      ! end of the first contact phase (later light taps of the vibrating bar do not count)
      if (in_contact .and. abs(s%walls(1)%force(1)) == 0.0_wp) then
        t_end_contact = s%t - s%dt
        in_contact = .false.
      end if
    end do
    call check(stat == 0, 'run ok: '//errmsg)
    pm = momentum(s)
    vrebound = pm(1)/sum(s%p%mass)
    call check_close(t_first, gap0/V, 'contact begins at gap / V (within 2 steps)', &
                     atol=2.0_wp*dt_contact)
    call check_close(t_end_contact - t_first, 2.0_wp*L/c, 'contact duration = 2 L / c', &
                     rtol=0.03_wp)
    call check_close(vrebound, V, 'rebound speed = impact speed', rtol=0.03_wp)
    print '(a,a8,a,f8.4,a,f8.4)', '  bar ', trim(basis_names(b)), ': contact time / (2L/c) = ', &
      (t_end_contact - t_first)/(2.0_wp*L/c), ', rebound / V = ', vrebound/V
  end subroutine test_bar_impact

  !> Two identical elastic rings colliding head on, no other forces: momentum constant,
  !! energy nearly conserved with FLIP.
  subroutine test_ring_collision()
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: p0(2), e0, pscale, emax_err
    integer :: stat, k
    character(len=:), allocatable :: errmsg
    call begin_test('two elastic rings colliding')
    cfg = base_case(1.0e6_wp, 0.3_wp, 1000.0_wp, 0.05_wp, 0.0_wp, BASIS_CPDI2, SCHEME_MUSL, &
                    PLANE_STRAIN)
    call add_ring(cfg, [-0.52_wp, 0.0_wp], 0.4_wp, 0.5_wp, 4, [1.0_wp, 0.0_wp])
    call add_ring(cfg, [0.52_wp, 0.0_wp], 0.4_wp, 0.5_wp, 4, [-1.0_wp, 0.0_wp])
    cfg%run%t_end = 0.3_wp
    call must_setup(cfg, s)
    p0 = momentum(s)
    pscale = sum(s%p%mass)*1.0_wp
    e0 = s%e0
    emax_err = 0.0_wp
    do k = 1, 1000000
      if (s%t >= s%prm%t_end) exit
      call solver_step(s, stat, errmsg)
      if (stat /= 0) exit
      emax_err = max(emax_err, abs(s%e_kin + s%e_strain + s%e_plastic - e0)/e0)
    end do
    call check(stat == 0, 'run ok: '//errmsg)
    call check_close(momentum(s), p0, 'total momentum constant', atol=1.0e-10_wp*pscale)
    call check_close(emax_err, 0.0_wp, 'energy conserved within 2 %', atol=0.02_wp)
    print '(a,es10.3)', '  rings: largest relative energy error ', emax_err
  end subroutine test_ring_collision
end program test_solver
