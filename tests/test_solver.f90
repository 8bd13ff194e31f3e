!> Solver tests against conservation laws and closed forms (issue 3):
!! P2G/G2P conservation, free translation, elastic bar on a rigid target, colliding rings.
! SPDX-License-Identifier: MIT
program test_solver
  !$ use omp_lib, only: omp_set_num_threads
  use mpm_kinds, only: wp
  use mpm_constants, only: BASIS_LINEAR, BASIS_CPDI2, basis_names, &
                           SCHEME_USL, SCHEME_MUSL, scheme_names, PLANE_STRESS, &
                           PLANE_STRAIN, MODEL_ELASTIC, CONTACT_FRICTIONLESS
  use mpm_config, only: config_t
  use mpm_scene_builder, only: scene_new, scene_add_material, scene_add_rect, scene_add_ring
  use mpm_solver, only: sim_t, solver_step, solver_init_energy
  use testing, only: begin_test, check, check_close, finish_tests
  use testing_sim, only: must_setup
  implicit none
  integer :: ib, is

  !> What the elastic bar run measured.
  type :: bar_result_t
    integer :: stat = 0
    real(wp) :: t_first = -1.0_wp      !! start of the first contact [s]
    real(wp) :: t_last = -1.0_wp       !! its end [s]
    real(wp) :: dt_contact = 0.0_wp    !! time step at its start [s]
    real(wp) :: impulse = 0.0_wp       !! impulse on the wall over it [N s/m]
    real(wp) :: plateau = 0.0_wp       !! mean wall force over its middle half [N/m]
    real(wp) :: vrebound = 0.0_wp      !! speed of the mass centre at the end [m/s]
    real(wp) :: t_half_on = -1.0_wp    !! first time the force exceeds half rho c V A [s]
    real(wp) :: t_half_off = -1.0_wp   !! last time it does, in the first contact [s]
  end type bar_result_t

  call test_transfer_conservation()
  do ib = BASIS_LINEAR, BASIS_CPDI2
    do is = SCHEME_USL, SCHEME_MUSL
      call test_free_translation(ib, is)
    end do
  end do
  do ib = BASIS_LINEAR, BASIS_CPDI2
    call test_bar_impact(ib)
  end do
  call test_bar_order()
  call test_ring_collision()
  call finish_tests('test_solver')

contains

  !> A one-material case: elastic, E, nu, rho; no bodies or walls yet (mpm_scene_builder).
  function base_case(E, nu, rho, h, t_end, basis, scheme, plane) result(cfg)
    real(wp), intent(in) :: E, nu, rho, h, t_end
    integer, intent(in) :: basis, scheme, plane
    type(config_t) :: cfg
    cfg = scene_new('test', t_end, h, basis, scheme, plane)
    cfg%run%cfl = 0.2_wp         ! the step these tests were written for (not automatic)
    cfg%run%check_units = .false.  ! unit-free cases (rings of 1.25 m, E of 1e3)
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

  function momentum(s) result(pm)
    type(sim_t), intent(in) :: s
    real(wp) :: pm(2)
    integer :: ip
    pm = 0.0_wp
    do ip = 1, s%p%np
      pm = pm + s%p%mass(ip)*s%p%v(:, ip)
    end do
  end function momentum

  !> A free elastic ring with a random velocity field, 30 steps at the stable time step: the
  !! transfers conserve mass and the internal forces of the real stresses conserve momentum
  !! to round-off (partition of unity), with 1 and 2 threads, for every basis.
  subroutine test_transfer_conservation()
    type(config_t) :: cfg
    type(sim_t) :: s
    integer :: b, nthreads, stat
    real(wp) :: m0, p0(2), r(2), smax
    character(len=:), allocatable :: errmsg
    integer :: ip, k
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
        call solver_init_energy(s)           ! E0 of the new velocities (energy balance)
        ! the stable time step (cfl 0.2) for 30 steps: the random velocity field strains the
        ! ring, so the internal forces of the later steps come from real stresses; they sum to
        ! zero over the nodes (sum grad phi = 0), so momentum is conserved to round-off
        m0 = sum(s%p%mass)
        p0 = momentum(s)
        stat = 0
        do k = 1, 30
          call solver_step(s, stat, errmsg)
          if (stat /= 0) exit
        end do
        call check(stat == 0, 'steps ok')
        smax = maxval(abs(s%p%stress))
        call check(smax > 1.0e-3_wp*cfg%materials(1)%E, 'real stresses: largest |stress| '// &
                   'above 1e-3 E')
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
    real(wp), allocatable :: x0(:, :)
    integer :: stat, k
    character(len=:), allocatable :: errmsg
    call begin_test('free translation, '//trim(basis_names(b))//' '//trim(scheme_names(scheme)))
    v = [3.0_wp, -2.0_wp]
    cfg = base_case(1.0e3_wp, 0.3_wp, 1.0_wp, 0.1_wp, 0.02_wp, b, scheme, PLANE_STRAIN)
    call add_ring(cfg, [0.0_wp, 0.0_wp], 0.75_wp, 1.25_wp, 4, v)
    call must_setup(cfg, s)
    p0 = momentum(s)
    x0 = s%p%x(:, 1:s%p%np)
    do k = 1, 100000
      if (s%t >= s%prm%t_end) exit
      call solver_step(s, stat, errmsg)
      if (stat /= 0) exit
    end do
    call check(stat == 0, 'run ok: '//errmsg)
    call check(maxval(abs(s%p%stress)) < 1.0e-9_wp*cfg%materials(1)%E, 'stress stays zero')
    call check_close(momentum(s), p0, 'momentum constant', rtol=1.0e-12_wp)
    ! every particle where the exact motion puts it: x0 + v t (round-off over the steps)
    do k = 1, 2
      x0(k, :) = x0(k, :) + v(k)*s%t
    end do
    call check_close(reshape(s%p%x(:, 1:s%p%np), [2*s%p%np]), reshape(x0, [2*s%p%np]), &
                     'positions = x0 + v t', atol=1.0e-12_wp*1.25_wp)
    call check_close(s%p%v(1, s%p%np), v(1), 'velocity unchanged', rtol=1.0e-12_wp)
  end subroutine test_free_translation

  !> Slender elastic bar on a rigid frictionless target (docs/verification.md): the 1-D wave
  !! solution (c = sqrt(E / rho), plane stress) is a force rho c V A (A = 2 h per unit depth)
  !! for 2 L / c, after which the bar leaves with its impact speed: impulse 2 m V. L / h = 100,
  !! every basis. The contact time is read where the force crosses half the plateau (the
  !! penalty contact rises and falls over a few steps, and a vibrating bar taps the wall
  !! lightly after leaving it). Measured: rebound 0.994-0.996 V, contact time 1.007-1.008
  !! (2L/c), plateau within 0.1 %, energy error 0.1-0.4 %; with the node contact of before
  !! the rebound was 0.967 V at this L/h.
  subroutine test_bar_impact(b)
    integer, intent(in) :: b
    real(wp), parameter :: L = 1.0_wp, V = 0.01_wp, gap0 = 0.002_wp, E = 100.0_wp, rho = 1.0_wp
    type(bar_result_t) :: r
    real(wp) :: c, mass, h
    call begin_test('elastic bar on a rigid target, '//trim(basis_names(b)))
    c = sqrt(E/rho)
    h = L/100.0_wp
    mass = rho*L*2.0_wp*h
    r = bar_run(b, 100)
    call check(r%stat == 0, 'run ok')
    call check_close(r%t_first, gap0/V, 'contact begins at gap / V (within 2 steps)', &
                     atol=2.0_wp*r%dt_contact)
    call check_close(r%t_half_off - r%t_half_on, 2.0_wp*L/c, &
                     'contact duration = 2 L / c (1 %, at half force)', rtol=0.01_wp)
    call check_close(r%vrebound, V, 'rebound speed = impact speed (1 %)', rtol=0.01_wp)
    call check_close(r%impulse, 2.0_wp*mass*V, 'impulse on the wall = 2 m V (1-D theory, 1 %)', &
                     rtol=0.01_wp)
    call check_close(r%plateau, rho*c*V*2.0_wp*h, 'contact force = rho c V A (1-D theory, 1 %)', &
                     rtol=0.01_wp)
    print '(a,a8,a,f8.4,a,f8.4,a,f8.4,a,f8.4)', '  bar ', trim(basis_names(b)), &
      ': contact time / (2L/c) = ', (r%t_half_off - r%t_half_on)/(2.0_wp*L/c), &
      ', rebound / V = ', r%vrebound/V, ', impulse / 2mV = ', r%impulse/(2.0_wp*mass*V), &
      ', force / rho c V A = ', r%plateau/(rho*c*V*2.0_wp*h)
  end subroutine test_bar_impact

  !> The elastic bar with CPDI2 at L/h = 80, 160, 320: the rebound stays within 1 % of V at
  !! every resolution (the node contact of before lost 4.2, 2.5, 1.3 %, first order in h: the
  !! energy of the nodes it stopped). Measured 0.73, 0.51, 0.45 %.
  subroutine test_bar_order()
    integer, parameter :: nl(3) = [80, 160, 320]
    real(wp) :: deficit(3)
    type(bar_result_t) :: r
    integer :: k
    call begin_test('elastic bar: rebound within 1 % at L/h = 80, 160, 320 (cpdi2)')
    do k = 1, 3
      r = bar_run(BASIS_CPDI2, nl(k))
      call check(r%stat == 0, 'run ok')
      deficit(k) = 1.0_wp - r%vrebound/0.01_wp
    end do
    print '(a,3f8.4)', '  bar cpdi2 rebound deficit at L/h = 80, 160, 320:', deficit
    call check(all(abs(deficit) < 0.01_wp), 'rebound within 1 % of V at every L/h')
    call check(deficit(3) <= deficit(1), 'the deficit does not grow under refinement')
  end subroutine test_bar_order

  !> Run the bar (L = 1, width 2 h, E = 100, rho = 1, nu = 0.3, plane stress, 2 particles per
  !! cell, V = 0.01, 0.002 from the wall) with L / h = nl and measure the first contact.
  function bar_run(b, nl) result(r)
    integer, intent(in) :: b, nl
    type(bar_result_t) :: r
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp), parameter :: E = 100.0_wp, rho = 1.0_wp, L = 1.0_wp, V = 0.01_wp
    real(wp), parameter :: gap0 = 0.002_wp
    real(wp) :: c, h, pm(2), t_mid, fsum, tsum
    integer :: stat, k
    logical :: in_contact
    character(len=:), allocatable :: errmsg
    c = sqrt(E/rho)
    h = L/real(nl, wp)
    cfg = base_case(E, 0.3_wp, rho, h, gap0/V + 2.0_wp*L/c + 0.03_wp, b, SCHEME_MUSL, &
                    PLANE_STRESS)
    call add_rect(cfg, [gap0 + 0.5_wp*L, 0.0_wp], [L, 2.0_wp*h], 2*nl, 4, [-V, 0.0_wp])
    deallocate(cfg%walls)
    allocate(cfg%walls(1))
    cfg%walls(1)%point = [0.0_wp, 0.0_wp]
    cfg%walls(1)%normal = [1.0_wp, 0.0_wp]
    cfg%walls(1)%contact_id = CONTACT_FRICTIONLESS
    call must_setup(cfg, s)
    r%t_first = -1.0_wp
    r%t_last = -1.0_wp
    r%dt_contact = 0.0_wp
    r%impulse = 0.0_wp
    in_contact = .false.
    fsum = 0.0_wp
    tsum = 0.0_wp
    t_mid = gap0/V + 0.5_wp*L/c     ! the middle half of the theoretical contact
    stat = 0
    do k = 1, 10000000
      if (s%t >= s%prm%t_end) exit
      call solver_step(s, stat, errmsg)
      if (stat /= 0) exit
      if (abs(s%walls(1)%force(1)) > 0.0_wp .and. r%t_first < 0.0_wp) then
        r%t_first = s%t - s%dt
        r%dt_contact = s%dt
        in_contact = .true.
      end if
      ! end of the first contact phase (later light taps of the vibrating bar do not count)
      if (in_contact .and. abs(s%walls(1)%force(1)) == 0.0_wp) then
        r%t_last = s%t - s%dt
        in_contact = .false.
      end if
      if (in_contact) r%impulse = r%impulse + s%walls(1)%impulse(1)
      if (in_contact .and. abs(s%walls(1)%force(1)) > 0.5_wp*rho*c*V*2.0_wp*h) then
        if (r%t_half_on < 0.0_wp) r%t_half_on = s%t - 0.5_wp*s%dt
        r%t_half_off = s%t - 0.5_wp*s%dt
      end if
      if (s%t - 0.5_wp*s%dt > t_mid .and. s%t - 0.5_wp*s%dt < t_mid + L/c) then
        fsum = fsum - s%walls(1)%force(1)*s%dt     ! force(1) < 0: the bar pushes the wall
        tsum = tsum + s%dt
      end if
    end do
    r%stat = stat
    pm = momentum(s)
    r%vrebound = pm(1)/sum(s%p%mass)
    r%plateau = fsum/max(tsum, tiny(1.0_wp))
  end function bar_run

  !> Two identical elastic rings colliding head on, no other forces: momentum constant,
  !! energy nearly conserved with FLIP.
  subroutine test_ring_collision()
    type(config_t) :: cfg
    type(sim_t) :: s
    real(wp) :: p0(2), e0, pscale, emax_err, ebook_err
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
    ebook_err = 0.0_wp
    do k = 1, 1000000
      if (s%t >= s%prm%t_end) exit
      call solver_step(s, stat, errmsg)
      if (stat /= 0) exit
      emax_err = max(emax_err, abs(s%e_kin + s%e_strain + s%e_plastic - e0)/e0)
      ebook_err = max(ebook_err, abs(s%e_kin + s%e_strain + s%e_plastic + s%e_contact_loss &
                                     - e0)/e0)
    end do
    call check(stat == 0, 'run ok: '//errmsg)
    call check_close(momentum(s), p0, 'total momentum constant', atol=1.0e-10_wp*pscale)
    ! the rings are two bodies: each has its own velocity field and they meet by the contact
    ! between bodies (docs/method.md), which dissipates at impact: 5.8 % here (1.6 % for the
    ! elastic aluminium rings of tests/test_body_contact.py); that loss is booked in
    ! contact_loss, with which the balance closes to 0.41 %
    call check_close(emax_err, 0.0_wp, 'energy conserved within 7 % without contact_loss', &
                     atol=0.07_wp)
    call check_close(ebook_err, 0.0_wp, 'with contact_loss within 1 %', atol=0.01_wp)
    print '(a,es10.3,a,es10.3)', '  rings: largest relative energy error ', emax_err, &
      ', with contact_loss ', ebook_err
  end subroutine test_ring_collision
end program test_solver
