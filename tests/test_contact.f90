!> The surface-point wall constraint (mpm_surface_contact) against closed forms: one point on a
!! cell of four nodes (the impulse lambda = deficit / sum N^2/m and dv_i = lambda N_i / m_i,
!! computed here independently), momentum given = impulse, separation, gaps, Coulomb bound,
!! mu = 0 equal to frictionless, stick, and several points sharing nodes.
! SPDX-License-Identifier: MIT
program test_contact
  use mpm_kinds, only: wp
  use mpm_constants, only: CONTACT_FRICTIONLESS, CONTACT_COULOMB, CONTACT_STICK
  use mpm_surface_contact, only: surface_work_t, surface_constrain
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  integer, parameter :: nx = 4, ny = 4, nn = nx*ny
  real(wp) :: mass(nn), vel(2, nn), dvel(2, nn), v0(2, nn), imp(2), xs(2, 3), gap(3)
  real(wp) :: w4(4), lam, s, vc(2), dt, mom0(2), mom1(2), tang(2), vt0, imp_f(2), vel_f(2, nn)
  real(wp) :: n(2)
  integer :: nodes(4), k
  type(surface_work_t) :: wk

  dt = 1.0e-3_wp
  call setup()
  ! ---- one point, frictionless, wall below (normal +y), approaching at -2 m/s, no gap
  call begin_test('one point: closed-form impulse and node changes')
  xs(:, 1) = [1.3_wp, 1.0_wp]                 ! on the node row j = 1, cell (1, 1)
  gap(1) = 0.0_wp
  n = [0.0_wp, 1.0_wp]
  nodes = [1 + 1 + nx*1, 2 + 1 + nx*1, 1 + 1 + nx*2, 2 + 1 + nx*2]
  w4 = [0.7_wp, 0.3_wp, 0.0_wp, 0.0_wp]
  s = sum(w4**2/mass(nodes))
  vc = matmul(vel(:, nodes), w4)
  lam = (0.0_wp - vc(2))/s                     ! target 0: touch, do not cross
  v0 = vel
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_FRICTIONLESS, 0.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, &
                         dvel, imp, wk)
  call check(lam > 0.0_wp, 'the wall pushes')
  do k = 1, 4
    call check_close(vel(2, nodes(k)) - v0(2, nodes(k)), lam*w4(k)/mass(nodes(k)), &
                     'dv_i = lambda N_i / m_i', rtol=1e-12_wp, atol=1e-14_wp)
  end do
  call check_close(vel(1, :), v0(1, :), 'frictionless: tangential velocities unchanged', &
                   atol=0.0_wp)
  call check_close(dot_product(matmul(vel(:, nodes), w4), n), 0.0_wp, &
                   'the point no longer approaches the wall', atol=1e-13_wp)
  call check_close(dvel(2, :) - 0.0_wp, vel(2, :) - v0(2, :), 'dvel gets the same change', &
                   atol=1e-15_wp)
  mom0 = matmul(v0, mass); mom1 = matmul(vel, mass)
  call check_close(imp, mom1 - mom0, 'impulse = momentum given to the nodes', rtol=1e-13_wp, &
                   atol=1e-16_wp)
  call check_close(imp(2), lam*sum(w4), 'impulse = lambda sum N', rtol=1e-13_wp)

  ! ---- separating point: nothing happens
  call begin_test('separation and gap')
  call setup()
  vel(2, :) = 1.0_wp
  v0 = vel
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_FRICTIONLESS, 0.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, &
                         dvel, imp, wk)
  call check_close(vel(2, :), v0(2, :), 'a separating point is not held', atol=0.0_wp)
  call check_close(imp, [0.0_wp, 0.0_wp], 'no impulse when separating', atol=0.0_wp)
  ! a gap of 1 mm closed at 2 m/s within 1 ms: the point may approach at 1 m/s only
  call setup()
  gap(1) = 1.0e-3_wp
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_FRICTIONLESS, 0.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, &
                         dvel, imp, wk)
  call check_close(dot_product(matmul(vel(:, nodes), w4), n), -gap(1)/dt, &
                   'the point closes its gap exactly in the step', rtol=1e-12_wp)
  ! a gap too wide to close: nothing happens
  call setup()
  gap(1) = 3.0e-3_wp
  v0 = vel
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_FRICTIONLESS, 0.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, &
                         dvel, imp, wk)
  call check_close(reshape(vel, [2*nn]), reshape(v0, [2*nn]), 'a point that cannot reach the wall is free', atol=0.0_wp)
  ! a moving wall: the relative velocity counts
  call setup()
  gap(1) = 0.0_wp
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_FRICTIONLESS, 0.0_wp, n, [0.5_wp, 3.0_wp], dt, .true., vel, &
                         dvel, imp, wk)
  call check_close(dot_product(matmul(vel(:, nodes), w4), n), 3.0_wp, &
                   'a platen moving up at 3 m/s pushes the point at 3 m/s', rtol=1e-12_wp)

  ! ---- friction
  call begin_test('friction laws')
  gap(1) = 0.0_wp
  tang = [-n(2), n(1)]
  call setup()
  vt0 = dot_product(matmul(vel(:, nodes), w4), tang)
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_FRICTIONLESS, 0.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, &
                         dvel, imp_f, wk)
  vel_f = vel
  call setup()
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_COULOMB, 0.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, dvel, &
                         imp, wk)
  call check_close(reshape(vel, [2*nn]), reshape(vel_f, [2*nn]), 'coulomb with mu = 0 equals frictionless', atol=0.0_wp)
  call setup()
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_COULOMB, 0.1_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, dvel, &
                         imp, wk)
  call check(abs(vt0) > 0.0_wp, 'the point slides before contact')
  call check_close(abs(dot_product(imp, tang)), 0.1_wp*dot_product(imp, n), &
                   'sliding: |friction impulse| = mu * normal impulse', rtol=1e-12_wp)
  call check(dot_product(imp, tang)*vt0 < 0.0_wp, 'friction opposes the sliding')
  call check(abs(dot_product(matmul(vel(:, nodes), w4), tang)) < abs(vt0), &
             'friction slows the sliding')
  call setup()
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_COULOMB, 100.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, dvel, &
                         imp, wk)
  call check_close(dot_product(matmul(vel(:, nodes), w4), tang), 0.0_wp, &
                   'mu large: the point sticks', atol=1e-12_wp)
  call setup()
  call surface_constrain(1, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_STICK, 0.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, dvel, &
                         imp, wk)
  call check_close(matmul(vel(:, nodes), w4), [0.0_wp, 0.0_wp], &
                   'stick: the point moves with the wall', atol=1e-12_wp)

  ! ---- three points sharing nodes, an inclined wall
  call begin_test('points sharing nodes')
  call setup()
  n = [0.6_wp, 0.8_wp]
  xs(:, 1) = [1.2_wp, 1.1_wp]
  xs(:, 2) = [1.7_wp, 1.4_wp]
  xs(:, 3) = [2.3_wp, 1.2_wp]
  gap = [0.0_wp, 0.5e-3_wp, 0.0_wp]
  v0 = vel
  call surface_constrain(3, xs, gap, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, &
                         CONTACT_FRICTIONLESS, 0.0_wp, n, [0.0_wp, 0.0_wp], dt, .true., vel, &
                         dvel, imp, wk)
  do k = 1, 3
    call check(point_vn(xs(:, k)) >= -max(gap(k), 0.0_wp)/dt - 1e-9_wp, &
               'every point satisfies its constraint')
  end do
  call check(any([(abs(point_vn(xs(:, k)) + max(gap(k), 0.0_wp)/dt) < 1e-9_wp, k = 1, 3)]), &
             'at least one point is held exactly at its limit')
  mom0 = matmul(v0, mass); mom1 = matmul(vel, mass)
  call check_close(imp, mom1 - mom0, 'impulse = momentum change of all nodes', rtol=1e-12_wp)
  call check(abs(imp(1)*n(2) - imp(2)*n(1)) <= 1e-12_wp*sqrt(sum(imp**2)), &
             'frictionless: the impulse is along the normal')
  call check(wk%sweeps < 200, 'the sweeps converge')
  call finish_tests('test_contact')

contains

  subroutine setup()
    integer :: i
    do i = 1, nn
      mass(i) = 1.0_wp + 0.1_wp*real(mod(7*i, 5), wp)
      vel(:, i) = [0.3_wp + 0.05_wp*real(mod(3*i, 4), wp), -2.0_wp - 0.1_wp*real(mod(i, 3), wp)]
    end do
    dvel = 0.0_wp
  end subroutine setup

  real(wp) function point_vn(x) result(vn)
    real(wp), intent(in) :: x(2)
    integer :: i0, j0, ids(4)
    real(wp) :: ww(4), fx, fy
    i0 = floor(x(1)); j0 = floor(x(2))
    fx = x(1) - real(i0, wp); fy = x(2) - real(j0, wp)
    ww = [(1.0_wp - fx)*(1.0_wp - fy), fx*(1.0_wp - fy), (1.0_wp - fx)*fy, fx*fy]
    ids = [1 + i0 + nx*j0, 2 + i0 + nx*j0, 1 + i0 + nx*(j0 + 1), 2 + i0 + nx*(j0 + 1)]
    vn = dot_product(matmul(vel(:, ids), ww), n)
  end function point_vn
end program test_contact
