!> &solver deterministic = .true. (issue 6): bit-identical results with 1 and 2 threads, and
!! agreement to round-off (rtol 1e-12) with the default per-thread scatter, on a short
!! elastic-plastic ring impact (contact, a 'slip' mirror plane, gravity, damping); also with
!! volumetric = 'fbar' (its node sums are serial, its particle loops parallel).
! SPDX-License-Identifier: MIT
program test_deterministic
  !$ use omp_lib, only: omp_set_num_threads
  use mpm_kinds, only: wp
  use mpm_constants, only: BASIS_UGIMP, BASIS_CPDI2, basis_names, SCHEME_USF, SCHEME_MUSL, &
                           scheme_names, PLANE_STRAIN, MODEL_J2, RATE_NONE, SHAPE_RING, &
                           SECTOR_HALF, CONTACT_FRICTIONLESS, VOLUMETRIC_STANDARD, &
                           VOLUMETRIC_FBAR
  use mpm_config, only: config_t
  use mpm_setup, only: setup_sim
  use mpm_solver, only: sim_t, solver_step
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  integer, parameter :: nsteps = 40
  integer :: volumetric = VOLUMETRIC_STANDARD   ! &solver volumetric of ring_case

  call compare(BASIS_CPDI2, SCHEME_MUSL)
  call compare(BASIS_UGIMP, SCHEME_USF)
  volumetric = VOLUMETRIC_FBAR
  call compare(BASIS_CPDI2, SCHEME_MUSL)
  !$ call omp_set_num_threads(2)
  call finish_tests('test_deterministic')

contains

  !> Half ring (J2, plane strain) falling onto a rigid frictionless target under gravity, with
  !! mass-proportional damping; the cut plane is a 'slip' mirror.
  function ring_case(basis, scheme, deterministic) result(cfg)
    integer, intent(in) :: basis, scheme
    logical, intent(in) :: deterministic
    type(config_t) :: cfg
    cfg%file = 'test'
    cfg%run%title = 'test'
    cfg%run%t_end = 1.0_wp
    cfg%run%cfl = 0.2_wp
    cfg%run%gravity = [0.0_wp, -50.0_wp]
    cfg%solver%basis_id = basis
    cfg%solver%scheme_id = scheme
    cfg%solver%plane_id = PLANE_STRAIN
    cfg%solver%damping = 2.0_wp
    cfg%solver%deterministic = deterministic
    cfg%solver%volumetric_id = volumetric
    cfg%grid%h = 0.025_wp
    cfg%grid%fitted = .true.
    allocate(cfg%materials(1), cfg%bodies(1), cfg%walls(1), cfg%probes(0))
    cfg%materials(1)%name = 'm'
    cfg%materials(1)%model_id = MODEL_J2
    cfg%materials(1)%rate_law_id = RATE_NONE
    cfg%materials(1)%E = 1.0e6_wp
    cfg%materials(1)%nu = 0.3_wp
    cfg%materials(1)%rho = 1000.0_wp
    cfg%materials(1)%sigma_y = 2.0e3_wp
    cfg%materials(1)%hardening = 1.0e4_wp
    cfg%bodies(1)%shape_id = SHAPE_RING
    cfg%bodies(1)%material_id = 1
    cfg%bodies(1)%sector_id = SECTOR_HALF
    cfg%bodies(1)%center = [0.0_wp, 0.505_wp]
    cfg%bodies(1)%r_inner = 0.4_wp
    cfg%bodies(1)%r_outer = 0.5_wp
    cfg%bodies(1)%n_thick = 6
    cfg%bodies(1)%n_circ = 0
    cfg%bodies(1)%velocity = [0.5_wp, -5.0_wp]
    cfg%walls(1)%point = [0.0_wp, 0.0_wp]
    cfg%walls(1)%normal = [0.0_wp, 1.0_wp]
    cfg%walls(1)%contact_id = CONTACT_FRICTIONLESS
  end function ring_case

  !> nsteps steps with the given thread count; every loop runs its parallel code path.
  function run(basis, scheme, deterministic, threads) result(s)
    integer, intent(in) :: basis, scheme, threads
    logical, intent(in) :: deterministic
    type(sim_t) :: s
    integer :: stat, k
    character(len=:), allocatable :: errmsg
    !$ call omp_set_num_threads(threads)
    call setup_sim(ring_case(basis, scheme, deterministic), s, stat, errmsg)
    call check(stat == 0, 'setup_sim: '//errmsg)
    if (stat /= 0) error stop 1
    s%prm%parallel_min = 0
    s%prm%colour_band = 100                    ! several bands of the deterministic sweep
    do k = 1, nsteps
      call solver_step(s, stat, errmsg)
      if (stat /= 0) exit
    end do
    call check(stat == 0, 'run ok: '//errmsg)
  end function run

  subroutine compare(basis, scheme)
    integer, intent(in) :: basis, scheme
    type(sim_t) :: d1, d2, f1, f2
    character(len=:), allocatable :: what
    what = trim(basis_names(basis))//' '//trim(scheme_names(scheme))
    if (volumetric == VOLUMETRIC_FBAR) what = what//', fbar'
    d1 = run(basis, scheme, .true., 1)
    d2 = run(basis, scheme, .true., 2)
    f1 = run(basis, scheme, .false., 1)
    f2 = run(basis, scheme, .false., 2)

    call begin_test('deterministic, 1 and 2 threads bit-identical, '//what)
    call check(maxval(abs(d1%walls(1)%impulse_acc)) > 0.0_wp, 'the ring touched the target')
    call check(maxval(d1%p%eqps) > 0.0_wp, 'the ring yielded')
    call check(all(d1%p%x == d2%p%x), 'positions')
    call check(all(d1%p%v == d2%p%v), 'velocities')
    call check(all(d1%p%stress == d2%p%stress), 'stresses')
    call check(all(d1%p%F == d2%p%F), 'deformation gradients')
    call check(all(d1%p%eqps == d2%p%eqps), 'plastic strains')
    call check(all(d1%p%xc == d2%p%xc), 'domain corners')
    call check(all(d1%g%mass == d2%g%mass) .and. all(d1%g%mom == d2%g%mom), 'grid mass, momentum')
    call check(d1%e_kin == d2%e_kin .and. d1%e_strain == d2%e_strain .and. &
               d1%e_plastic == d2%e_plastic .and. d1%e_damped == d2%e_damped .and. &
               d1%w_gravity == d2%w_gravity, 'energies')
    call check(all(d1%walls(1)%impulse_acc == d2%walls(1)%impulse_acc) .and. &
               all(d1%walls(1)%force == d2%walls(1)%force), 'wall impulse and force')
    call check(d1%t == d2%t .and. d1%step == d2%step, 'time')

    print '(2a,es10.3,a,es10.3,a,f6.3)', '  ', what, maxval(abs(d1%p%x - f1%p%x)), &
      ' m largest position difference deterministic - default; wall impulse ', &
      d1%walls(1)%impulse_acc(2), ' N s/m; yielded fraction ', &
      real(count(d1%p%eqps > 0.0_wp), wp)/real(d1%p%np, wp)
    call begin_test('deterministic = default scatter to round-off, '//what)
    call agree(d1, f1, 'deterministic vs default, 1 thread')
    call agree(f2, f1, 'default, 2 threads vs 1 thread')
  end subroutine compare

  !> Particle state and energies of a and b agree to rtol 1e-12 (of each array's largest value).
  subroutine agree(a, b, what)
    type(sim_t), intent(in) :: a, b
    character(len=*), intent(in) :: what
    real(wp), parameter :: rtol = 1.0e-12_wp
    call check_close(reshape(a%p%x, [size(a%p%x)]), reshape(b%p%x, [size(b%p%x)]), &
                     what//': positions', rtol=rtol, atol=rtol*maxval(abs(b%p%x)))
    call check_close(reshape(a%p%v, [size(a%p%v)]), reshape(b%p%v, [size(b%p%v)]), &
                     what//': velocities', rtol=rtol, atol=rtol*maxval(abs(b%p%v)))
    call check_close(reshape(a%p%stress, [size(a%p%stress)]), &
                     reshape(b%p%stress, [size(b%p%stress)]), what//': stresses', rtol=rtol, &
                     atol=rtol*maxval(abs(b%p%stress)))
    call check_close(a%p%eqps, b%p%eqps, what//': plastic strains', rtol=rtol, &
                     atol=rtol*maxval(abs(b%p%eqps)))
    call check_close([a%e_kin, a%e_strain, a%e_plastic, a%e_damped, a%w_gravity], &
                     [b%e_kin, b%e_strain, b%e_plastic, b%e_damped, b%w_gravity], &
                     what//': energies', rtol=rtol)
    call check_close(a%walls(1)%impulse_acc, b%walls(1)%impulse_acc, what//': wall impulse', &
                     rtol=rtol, atol=rtol*maxval(abs(b%walls(1)%impulse_acc)))
  end subroutine agree
end program test_deterministic
