!> The surface contact with rigid walls (mpm_surface_contact) against closed forms: which points
!! are in contact and their penalty forces and energies (CPDI2 corners with their mass shares,
!! the deformed domains of the other bases), the force spread to the nodes with the bilinear
!! weights at the point and the impulse = momentum given to the active nodes, to round-off;
!! a single point mass bouncing on the wall (half period pi / omega, rebound speed); friction:
!! stick stops the slip, Coulomb is bounded by mu times the normal impulse, mu = 0 changes
!! nothing; points that share nodes; the tie of a 'bonded' wall (the points within reach at
!! t = 0, the spring -k d to the anchor carried with the wall, both ways and along the wall,
!! its energy 1/2 k |d|^2, its tangential force on the nodes, and no friction on tied points);
!! the energy of a step (surface_step_energy): the explicit update's own invariant through a
!! bounce off a moving wall, and 1/2 k d . d' for tied points.
! SPDX-License-Identifier: MIT
program test_contact
  !$ use omp_lib, only: omp_set_num_threads
  use mpm_kinds, only: wp
  use mpm_constants, only: pi, BASIS_CPDI1, BASIS_CPDI2, BASIS_UGIMP, BASIS_LINEAR, CONTACT_COULOMB, &
                           CONTACT_STICK, CONTACT_BONDED
  use mpm_particles, only: particles_t, particles_allocate, particle_corners
  use mpm_strings, only: itoa
  use mpm_surface_contact, only: surface_work_t, surface_points, surface_push, surface_friction, &
                                 surface_energy, surface_tie, surface_tied, surface_step_energy
  use mpm_contact, only: slip_span_columns
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  integer, parameter :: nx = 4, ny = 4, nn = nx*ny
  real(wp), parameter :: kf = 4.0e6_wp       ! stiffness per unit point mass [1/s^2]
  real(wp) :: mass(nn), force(2, nn), vel(2, nn), dvel(2, nn), v0(2, nn), imp(2), dt
  real(wp) :: nrm(2), w4(4), fsum(2)
  integer :: nodes(4), k, blk(2, 1)
  real(wp) :: wdummy(4, 1), gwdummy(2, 4, 1)
  type(surface_work_t) :: wk
  type(particles_t) :: p

  dt = 1.0e-4_wp
  nrm = [0.0_wp, 1.0_wp]
  blk = 0
  wdummy = 0.0_wp
  gwdummy = 0.0_wp

  ! ---- CPDI2: the corners behind the plane, mass shares, forces, energies
  call begin_test('CPDI2 corners in contact: forces and energies in closed form')
  call two_squares(p)                        ! two unit squares side by side, y in [-0.01, 0.99]
  call surface_points(p, BASIS_CPDI2, [0.0_wp, 0.0_wp], nrm, kf, .false., wk)
  call check(wk%npt == 3, 'the three bottom corners are in contact')
  ! bottom corners x = 0, 1, 2 at y = -0.01; mass shares m/4, m/2, m/4 (m = 2 per square)
  call check_close(wk%fn(1:3), kf*0.01_wp*[0.5_wp, 1.0_wp, 0.5_wp], 'f_c = kf m_c (-g_c)', &
                   rtol=1e-13_wp)
  call check_close(surface_energy(wk), 0.5_wp*kf*2.0_wp*0.01_wp**2, &
                   'energy = sum 1/2 kf m_c g_c^2', rtol=1e-13_wp)
  call surface_points(p, BASIS_CPDI2, [0.0_wp, -0.02_wp], nrm, kf, .false., wk)
  call check(wk%npt == 0, 'a plane below the body touches nothing')

  ! ---- uGIMP / CPDI1: the domain deformed with F
  call begin_test('uGIMP and CPDI1: the deformed domain touches')
  call two_squares(p)
  p%F(2, 2, :) = 0.9_wp                      ! compressed 10 % along y: half height 0.45
  call surface_points(p, BASIS_UGIMP, [0.0_wp, 0.06_wp], nrm, kf, .false., wk)
  ! centres at y = 0.49, bottom at 0.49 - 0.45 = 0.04: 0.02 behind the plane at 0.06
  call check(wk%npt == 4, 'two bottom corners of each particle')
  call check_close(wk%fn(1:4), [(kf*0.5_wp*0.02_wp, k = 1, 4)], 'f = kf m/4 (-g)', rtol=1e-12_wp)
  call surface_points(p, BASIS_UGIMP, [0.0_wp, 0.03_wp], nrm, kf, .false., wk)
  call check(wk%npt == 0, 'the undeformed square (bottom at -0.01) would touch, F r does not')
  p%r10(:, 1:2) = reshape([0.5_wp, 0.0_wp, 0.5_wp, 0.0_wp], [2, 2])
  p%r20(:, 1:2) = reshape([0.0_wp, 0.5_wp, 0.0_wp, 0.5_wp], [2, 2])
  call surface_points(p, BASIS_CPDI1, [0.0_wp, 0.06_wp], nrm, kf, .false., wk)
  call check(wk%npt == 4, 'CPDI1: the same corners x -+ F r10 -+ F r20')
  call random_cloud()

  ! ---- the force on the nodes and the exact impulse
  call begin_test('force spread with bilinear weights; impulse = momentum given')
  call grid_setup()
  call one_point([1.3_wp, 1.0_wp], -1.0e-3_wp, 2.0_wp)
  call surface_push(wk, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, 2, blk, wdummy, gwdummy, &
                    nrm, dt, force, imp)
  nodes = [1 + 1 + nx*1, 2 + 1 + nx*1, 1 + 1 + nx*2, 2 + 1 + nx*2]
  w4 = [0.7_wp, 0.3_wp, 0.0_wp, 0.0_wp]
  do k = 1, 4
    call check_close(force(2, nodes(k)), w4(k)*kf*2.0_wp*1.0e-3_wp, 'node force = N_i f_c', &
                     rtol=1e-12_wp, atol=1e-12_wp)
  end do
  call check_close(force(1, :), [(0.0_wp, k = 1, nn)], 'no tangential force', atol=0.0_wp)
  fsum = sum(force, dim=2)
  call check_close(imp, fsum*dt, 'impulse = sum of node forces times dt', rtol=1e-14_wp)
  call check_close(imp(2), kf*2.0_wp*1.0e-3_wp*dt, 'impulse = f_c dt (all nodes active)', &
                   rtol=1e-12_wp)
  ! an inactive node takes nothing and the impulse says so
  call grid_setup()
  mass(nodes(2)) = 0.0_wp
  call surface_push(wk, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, 2, blk, wdummy, gwdummy, &
                    nrm, dt, force, imp)
  call check_close(force(2, nodes(2)), 0.0_wp, 'inactive node: no force', atol=0.0_wp)
  call check_close(imp(2), 0.7_wp*kf*2.0_wp*1.0e-3_wp*dt, 'impulse counts active nodes only', &
                   rtol=1e-12_wp)

  call test_bounce()
  call test_step_energy()
  call test_friction()
  call test_slip_columns()
  call test_tie()
  call finish_tests('test_contact')

contains

  !> slip_span_columns against every node of random spans: the columns it keeps (i <= ib or
  !! i >= ia) hold every node that a slip plane acts on (node_walls' test: the node at most a
  !! millionth of a cell in front of it) and every node within a cell of it, for normals along +x, -x, +y, -y, oblique ones and
  !! ones with a tiny x component, over spans near, across and far from the plane; and it
  !! leaves columns out where the plane is oblique and far from part of the span (else
  !! the test could not tell it from keeping everything).
  subroutine test_slip_columns()
    real(wp), parameter :: h = 0.37_wp, tol = 1.0e-6_wp*h
    real(wp) :: origin(2), pw(2), nw(2), r(6), th, xn(2), d
    integer :: trial, i0, i1, j0, j1, ib, ia, i, j, missed, near, cut, kind
    call begin_test('slip planes: the columns a span keeps hold every node the plane acts on')
    origin = [-1.3_wp, 0.7_wp]
    missed = 0
    near = 0
    cut = 0
    do trial = 1, 20000
      call random_number(r)
      i0 = int(40.0_wp*r(1))
      i1 = i0 + int(30.0_wp*r(2))
      j0 = int(40.0_wp*r(3))
      j1 = j0 + int(4.0_wp*r(4))
      kind = mod(trial, 6)
      select case (kind)
      case (0); th = 0.0_wp                              ! +x
      case (1); th = pi                                  ! -x
      case (2); th = 0.5_wp*pi                           ! +y: along the columns
      case (3); th = 1.5_wp*pi                           ! -y
      case (4); th = 0.5_wp*pi + 1.0e-9_wp*(r(5) - 0.5_wp)  ! a tiny x component
      case default; th = 2.0_wp*pi*r(5)                  ! oblique
      end select
      nw = [cos(th), sin(th)]
      pw = origin + h*[80.0_wp*r(6) - 10.0_wp, 50.0_wp*r(5) - 5.0_wp]
      ib = i0 - 1
      ia = i1 + 1
      call slip_span_columns(origin, h, i0, i1, j0, j1, pw, nw, ib, ia)
      if (ib < i1 .and. ia > ib + 1 .and. ia > i0) cut = cut + 1
      do j = j0, j1
        do i = i0, i1
          xn = origin + h*real([i, j], wp)
          d = dot_product(xn - pw, nw)
          if (d - tol <= 0.0_wp .and. i > ib .and. i < ia) missed = missed + 1
          if (d <= 0.999_wp*h .and. i > ib .and. i < ia) near = near + 1
        end do
      end do
    end do
    call check(missed == 0, 'no node acted on is left out ('//itoa(missed)//' missed)')
    call check(near == 0, 'no node within a cell of the plane is left out, as the routine '// &
               'promises ('//itoa(near)//' left out)')
    call check(cut > 1000, 'columns are left out of '//itoa(cut)//' of 20000 spans')
  end subroutine test_slip_columns

  !> A 'bonded' wall: the two squares' bottom corners (gap -0.01) are tied, the top ones (0.99)
  !! not; a corner moved by (0.02, 0.03) with the wall shifted by (0.01, 0) takes -k d with
  !! d = (0.01, 0.03): normal -k 0.03, along the wall (t = [-1, 0]) +k 0.01; energy 1/2 k |d|^2;
  !! lifted clear of the wall the tied corners are still held (pulled back); the nodes get the
  !! tangential force too; friction leaves the tied points alone.
  subroutine test_tie()
    type(surface_work_t) :: wt
    real(wp) :: k2, ftot(2), ex, d(2)
    integer :: k
    real(wp), parameter :: mc(3) = [0.5_wp, 1.0_wp, 0.5_wp]   ! the corners' mass shares
    call begin_test('bonded wall: the tie in closed form')
    call two_squares(p)
    call surface_tie(p, BASIS_CPDI2, [0.0_wp, 0.0_wp], nrm, 0.5_wp, wt)
    call check(surface_tied(wt) == 3, 'the three bottom corners are tied, the top ones not')
    p%xc(:, 2) = p%xc(:, 2) + [0.02_wp, 0.03_wp]
    wt%shift = [0.01_wp, 0.0_wp]
    call surface_points(p, BASIS_CPDI2, [0.0_wp, 0.0_wp], nrm, kf, .false., wt)
    call check(wt%npt == 3 .and. all(wt%tied(1:3)), 'three tied points')
    k2 = kf*1.0_wp                           ! corner 2's mass share is 1
    call check_close(wt%fn(2), -k2*0.03_wp, 'normal: -k (g - g0)', rtol=1e-12_wp)
    call check_close(wt%ft(2), k2*0.01_wp, 'along the wall: -k d . t', rtol=1e-12_wp)
    ex = 0.5_wp*k2*(0.01_wp**2 + 0.03_wp**2) + 2.0_wp*0.5_wp*kf*0.5_wp*0.01_wp**2
    call check_close(surface_energy(wt), ex, 'energy 1/2 k |d|^2 (the others shifted by '// &
                     'the wall)', rtol=1e-12_wp)
    p%xc(2, 1:3) = 0.2_wp                    ! lifted clear of the wall
    wt%shift = 0.0_wp
    call surface_points(p, BASIS_CPDI2, [0.0_wp, 0.0_wp], nrm, kf, .false., wt)
    call check(wt%npt == 3 .and. all(wt%fn(1:3) < 0.0_wp), 'lifted: still held, pulled back')
    call grid_setup()
    call surface_push(wt, [-1.0_wp, -1.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, 2, blk, wdummy, &
                      gwdummy, nrm, dt, force, imp)
    ftot = sum(force, dim=2)                 ! the corner at x = 2 is off this 4 x 4 grid
    call check(wt%s(3) == 0.0_wp .and. all(wt%s(1:2) > 0.0_wp), 'two points on the grid')
    call check_close(ftot, [-sum(wt%ft(1:2)), sum(wt%fn(1:2))], 'node forces: fn n + ft t', &
                     rtol=1e-12_wp)
    call check_close(imp, ftot*dt, 'impulse = node forces times dt', rtol=1e-12_wp)
    ! the energy of the step: 1/2 k d . d' with d' = d + dt (v_c - v_w), v_c the bilinear
    ! interpolant of the node velocities; the point off the grid (no force) keeps 1/2 k |d|^2
    ex = 0.0_wp
    do k = 1, 2
      d = p%xc(:, k) - [real(k - 1, wp), -0.01_wp]
      ex = ex + 0.5_wp*kf*mc(k)*dot_product(d, d + dt*(vint(p%xc(:, k)) - [0.3_wp, -0.2_wp]))
    end do
    ex = ex + 0.5_wp*kf*mc(3)*0.21_wp**2
    call check_close(surface_step_energy(wt, nrm, [0.3_wp, -0.2_wp], vel, dt), ex, &
                     'energy of the step: 1/2 k d . d'' (tied points)', rtol=1e-12_wp)
    v0 = vel
    call surface_friction(wt, CONTACT_BONDED, 0.5_wp, nrm, [0.5_wp, 0.0_wp], vel, dvel, imp)
    call check_close(reshape(vel, [2*nn]), reshape(v0, [2*nn]), 'no friction on tied '// &
                     'points', atol=0.0_wp)
  end subroutine test_tie

  !> The bilinear interpolant at x of the node velocities vel (grid_setup's 4 x 4 grid of unit
  !! cells with node (0, 0) at (-1, -1)).
  function vint(x) result(vc)
    real(wp), intent(in) :: x(2)
    real(wp) :: vc(2), fx, fy
    integer :: i0, j0
    i0 = floor(x(1) + 1.0_wp)
    j0 = floor(x(2) + 1.0_wp)
    fx = x(1) + 1.0_wp - real(i0, wp)
    fy = x(2) + 1.0_wp - real(j0, wp)
    vc = (1.0_wp - fx)*(1.0_wp - fy)*vel(:, 1 + i0 + nx*j0) &
         + fx*(1.0_wp - fy)*vel(:, 2 + i0 + nx*j0) &
         + (1.0_wp - fx)*fy*vel(:, 1 + i0 + nx*(j0 + 1)) + fx*fy*vel(:, 2 + i0 + nx*(j0 + 1))
  end function vint

  !> Two unit squares side by side (CPDI2 tiling: 6 corners), mass 2 each, bottom at -0.01.
  subroutine two_squares(q)
    type(particles_t), intent(inout) :: q
    if (allocated(q%x)) deallocate(q%x, q%v, q%mass, q%vol0, q%vol, q%F, q%stress, q%eqps, &
      q%wplastic, q%r10, q%r20, q%half, q%corner, q%xc, q%mat, q%body)
    call particles_allocate(q, 2, 6)
    q%xc = reshape([0.0_wp, -0.01_wp, 1.0_wp, -0.01_wp, 2.0_wp, -0.01_wp, &
                    0.0_wp, 0.99_wp, 1.0_wp, 0.99_wp, 2.0_wp, 0.99_wp], [2, 6])
    q%corner(:, 1) = [1, 2, 5, 4]
    q%corner(:, 2) = [2, 3, 6, 5]
    q%x(:, 1) = [0.5_wp, 0.49_wp]
    q%x(:, 2) = [1.5_wp, 0.49_wp]
    q%mass = 2.0_wp
    q%half = 0.5_wp
  end subroutine two_squares

  !> The particles surface_points skips (their corners surely clear of the plane) change
  !! nothing: against the plain scan of every corner of every particle (particle_corners,
  !! deformed), the same points, forces and deepest gap, bit for bit and in order, for linear,
  !! uGIMP and CPDI1: (1) 3000 particles of random size, shape (F) and place, half of them
  !! within reach of the plane, scanned serially and in parallel on two threads (three chunks of
  !! the scan); (2) single particles far from the origin (|x| up to 1000 m, domains of 1e-5 m,
  !! so that the corners round at 1e-13 m) under planes tilted up to 0.5 rad through points
  !! within 2 ulps of the deepest corner: the cases a margin too small gets wrong.
  subroutine random_cloud()
    integer, parameter :: n = 3000, nfar = 700
    integer, parameter :: bases(3) = [BASIS_LINEAR, BASIS_UGIMP, BASIS_CPDI1]
    type(particles_t) :: q, one
    type(surface_work_t) :: ws, wpar
    real(wp) :: u(8), gmin, xw(2), xq(2, 4), th, tilt(2)
    real(wp), allocatable :: fn(:)
    integer, allocatable :: owner(:)
    integer :: ip, npt, ib, k, j, ic, bad
    call begin_test('surface points: the skipped particles are clear of the plane')
    call particles_allocate(q, n, 4*n)
    do ip = 1, n
      call random_number(u)
      call random_particle(q, ip, u, [2.0_wp*u(7), 0.3_wp + 0.2_wp*(u(8) - 0.5_wp)], 1.0_wp)
    end do
    do ib = 1, 3
      call plain_scan(q, bases(ib), [0.0_wp, 0.3_wp], nrm, npt, owner, fn, gmin)
      call surface_points(q, bases(ib), [0.0_wp, 0.3_wp], nrm, kf, .false., ws)
      call check(npt > 100 .and. npt < 4*n - 100, 'the plane cuts the cloud ('//itoa(npt)// &
                 ' points)')
      call check(same(ws, npt, owner, fn, gmin), 'serial: the plain scan''s points, bit for '// &
                 'bit, basis '//itoa(ib))
      !$ call omp_set_num_threads(2)
      call surface_points(q, bases(ib), [0.0_wp, 0.3_wp], nrm, kf, .true., wpar)
      !$ call omp_set_num_threads(1)
      call check(same(wpar, npt, owner, fn, gmin), 'two threads: the plain scan''s points, '// &
                 'bit for bit, basis '//itoa(ib))
    end do
    call particles_allocate(one, 1, 4)
    do ib = 1, 3
      bad = 0
      do ip = 1, nfar
        call random_number(u)
        call random_particle(one, 1, u, [1.0e3_wp*(u(7) - 0.5_wp), 1.0e3_wp*u(8)], 1.0e-3_wp)
        call random_number(th)
        tilt = [sin(th - 0.5_wp), cos(th - 0.5_wp)]     ! within 0.5 rad of +y
        xq = particle_corners(one, 1, bases(ib), deformed=.true.)
        ic = minloc(matmul(tilt, xq), dim=1)             ! the deepest corner along tilt
        do k = -2, 2
          do j = -2, 2
            xw = xq(:, ic) + [real(k, wp), real(j, wp)]*spacing(xq(:, ic))
            call plain_scan(one, bases(ib), xw, tilt, npt, owner, fn, gmin)
            call surface_points(one, bases(ib), xw, tilt, kf, .false., ws)
            if (.not. same(ws, npt, owner, fn, gmin)) bad = bad + 1
          end do
        end do
      end do
      call check(bad == 0, itoa(25*nfar)//' planes within 2 ulps of the deepest corner: '// &
                 itoa(bad)//' differ from the plain scan, basis '//itoa(ib))
    end do
  end subroutine random_cloud

  !> Particle ip of q: half sizes scale*(0.01 ... 0.05), F within 0.3 of the identity, at x.
  subroutine random_particle(q, ip, u, x, scale)
    type(particles_t), intent(inout) :: q
    integer, intent(in) :: ip
    real(wp), intent(in) :: u(8), x(2), scale
    q%half(:, ip) = scale*(0.01_wp + 0.04_wp*u(1:2))
    q%F(:, :, ip) = reshape([1.0_wp + 0.6_wp*(u(3) - 0.5_wp), 0.6_wp*(u(4) - 0.5_wp), &
                             0.6_wp*(u(5) - 0.5_wp), 1.0_wp + 0.6_wp*(u(6) - 0.5_wp)], [2, 2])
    q%x(:, ip) = x
    q%r10(:, ip) = [q%half(1, ip), 0.3_wp*q%half(2, ip)]
    q%r20(:, ip) = [-0.2_wp*q%half(1, ip), q%half(2, ip)]
    q%mass(ip) = 1.0_wp + u(1)
  end subroutine random_particle

  !> Every corner of every particle of q against the plane through xw with unit normal n: the
  !! points behind it (owner, force) in order and the deepest gap (<= 0).
  subroutine plain_scan(q, basis, xw, n, npt, owner, fn, gmin)
    type(particles_t), intent(in) :: q
    integer, intent(in) :: basis
    real(wp), intent(in) :: xw(2), n(2)
    integer, intent(out) :: npt
    integer, allocatable, intent(out) :: owner(:)
    real(wp), allocatable, intent(out) :: fn(:)
    real(wp), intent(out) :: gmin
    real(wp) :: xq(2, 4), d
    integer :: ip, a
    allocate(owner(4*q%np), fn(4*q%np))
    npt = 0
    gmin = 0.0_wp
    do ip = 1, q%np
      xq = particle_corners(q, ip, basis, deformed=.true.)
      do a = 1, 4
        d = dot_product(xq(:, a) - xw, n)
        gmin = min(gmin, d)
        if (d < 0.0_wp) then
          npt = npt + 1
          owner(npt) = ip
          fn(npt) = -kf*0.25_wp*q%mass(ip)*d
        end if
      end do
    end do
  end subroutine plain_scan

  !> The points of ws are those given, bit for bit, in order, and so is the deepest gap.
  logical function same(ws, npt, owner, fn, gmin)
    type(surface_work_t), intent(in) :: ws
    integer, intent(in) :: npt, owner(:)
    real(wp), intent(in) :: fn(:), gmin
    same = ws%npt == npt .and. ws%gmin == gmin
    if (same .and. npt > 0) same = all(ws%owner(1:npt) == owner(1:npt)) .and. &
                                   all(ws%fn(1:npt) == fn(1:npt))
  end function same

  !> A 4 x 4 grid of unit cells, node masses 1 to 2, no force, velocities set.
  subroutine grid_setup()
    integer :: n
    do n = 1, nn
      mass(n) = 1.0_wp + real(mod(7*n, 5), wp)/4.0_wp
      vel(:, n) = [0.3_wp*real(mod(n, 3), wp), -2.0_wp + 0.1_wp*real(n, wp)]
    end do
    force = 0.0_wp
    dvel = 0.0_wp
  end subroutine grid_setup

  !> The work arrays with one CPDI2-like point at x, gap g, mass m.
  subroutine one_point(x, g, m)
    real(wp), intent(in) :: x(2), g, m
    type(particles_t) :: q
    call particles_allocate(q, 1, 4)
    q%xc = reshape([x(1), x(2), x(1) + 0.1_wp, x(2) + 5.0_wp, x(1) + 0.1_wp, x(2) + 5.1_wp, &
                    x(1), x(2) + 5.1_wp], [2, 4])
    q%corner(:, 1) = [1, 2, 3, 4]
    q%mass = 4.0_wp*m                          ! the first corner's share is m
    call surface_points(q, BASIS_CPDI2, [0.0_wp, x(2) - g], nrm, kf, .false., wk)
    call check(wk%npt == 1, 'one point in contact')
  end subroutine one_point

  !> A point mass m on one node bouncing on the wall, integrated as the solver does (force at
  !! the start of the step, then velocity, then position): contact lasts half a period of
  !! omega = sqrt(kf), and it leaves with its impact speed (the penalty is conservative).
  subroutine test_bounce()
    real(wp) :: y, v, t, t_on, t_off, hstep, m1(nn), f1(2, nn), imp1(2), e_max
    type(particles_t) :: q
    type(surface_work_t) :: wb               ! its own: the corner masses differ
    integer :: it
    call begin_test('a point mass bouncing on the wall: contact time pi/omega, rebound speed')
    call particles_allocate(q, 1, 4)
    q%corner(:, 1) = [1, 2, 3, 4]
    q%mass = 4.0_wp                            ! corner 1 has mass 1, on node (1, 1) below
    m1 = 1.0_wp
    hstep = 2.0_wp*pi/sqrt(kf)/200.0_wp        ! 100 steps per contact
    y = 0.01_wp
    v = -1.0_wp
    t = 0.0_wp
    t_on = -1.0_wp
    t_off = -1.0_wp
    e_max = 0.0_wp
    do it = 1, 100000
      q%xc(:, 1) = [1.0_wp, 1.0_wp + y]         ! exactly on node (1, 1): N = 1 there
      q%xc(:, 2:4) = reshape([1.5_wp, 9.0_wp, 1.5_wp, 9.5_wp, 1.0_wp, 9.5_wp], [2, 3])
      call surface_points(q, BASIS_CPDI2, [0.0_wp, 1.0_wp], nrm, kf, .false., wb)
      f1 = 0.0_wp
      call surface_push(wb, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, m1, 0.0_wp, 2, blk, wdummy, gwdummy, &
                        nrm, hstep, f1, imp1)
      v = v + hstep*f1(2, 1 + 1 + nx)/m1(1 + 1 + nx)
      y = y + hstep*v
      t = t + hstep
      if (wb%npt > 0 .and. t_on < 0.0_wp) t_on = t - hstep
      if (wb%npt > 0) t_off = t
      e_max = max(e_max, abs(0.5_wp*v*v + surface_energy(wb)/1.0_wp - 0.5_wp))
      if (t_on > 0.0_wp .and. y > 0.0_wp .and. v > 0.0_wp) exit
    end do
    call check_close(t_off - t_on, pi/sqrt(kf), 'contact time = pi / omega (2 steps)', &
                     atol=2.0_wp*hstep)
    call check_close(v, 1.0_wp, 'rebound speed = impact speed (0.5 %)', rtol=5.0e-3_wp)
    call check(e_max < 0.05_wp, 'energy within 5 % through the contact (order omega dt)')
  end subroutine test_bounce

  !> The contact energy of a step against the explicit update's invariant: a rigid body of
  !! mass 1 (every node at its velocity) whose one CPDI2 corner of mass share 1 touches the
  !! wall (stiffness kf: omega = sqrt(kf)), at rest, struck by a wall moving at u = 1 (the start
  !! of the step a fraction phi of a step's travel below the corner) and thrown off at about
  !! 2 u, integrated as the solver does at omega dt = 0.5 (force at the start of the step,
  !! velocity, then position; the wall's work impulse times u). With E = 1/2 m v^2 + e - W:
  !! - e = surface_step_energy (1/2 k g g', the gaps at the start and end of the step): E is
  !!   the update's invariant, constant to round-off (1e-10 of 1/2 m u^2: the gaps, 1e-4, are
  !!   differences of positions near 1) over every step the point stays behind the wall, and
  !!   after the bounce within (omega dt)^2 / 8 of W (an error of second order, from the steps
  !!   of touch-down and lift-off, where the force law changes within the step);
  !! - e = surface_energy (1/2 k g^2 at the start of the step) is off by dt/2 f gdot, which
  !!   changes from step to step during the contact (the failing case: 0.24 of 1/2 m u^2).
  !! A particle's corner (linear basis) keeps the start-of-step energy.
  subroutine test_step_energy()
    real(wp), parameter :: u = 1.0_wp, mb = 1.0_wp, wdt = 0.5_wp
    real(wp), parameter :: phases(4) = [0.1_wp, 0.25_wp, 0.5_wp, 0.9_wp]
    type(particles_t) :: q
    type(surface_work_t) :: ws
    real(wp) :: hs, yw, v, w, e, eold, g0, g1, big, old_change, worst, lost, m1(nn), f1(2, nn), &
                imp1(2), v1(2, nn), es(2), prev(2)
    integer :: it, ip
    logical :: was_on
    call begin_test('the energy of a step: the invariant of the update through a bounce')
    hs = wdt/sqrt(kf)
    call particles_allocate(q, 1, 4)
    q%corner(:, 1) = [1, 2, 3, 4]
    q%mass = 4.0_wp                            ! corner 1's share is 1
    m1 = 1.0_wp
    big = 0.0_wp
    old_change = 0.0_wp
    worst = 0.0_wp
    do ip = 1, size(phases)
      q%xc = reshape([1.3_wp, 1.0_wp, 1.5_wp, 2.7_wp, 1.5_wp, 2.8_wp, 1.3_wp, 2.8_wp], [2, 4])
      yw = 1.0_wp - phases(ip)*u*hs
      v = 0.0_wp
      w = 0.0_wp
      prev = 0.0_wp
      was_on = .false.
      do it = 1, 1000
        g0 = q%xc(2, 1) - yw
        call surface_points(q, BASIS_CPDI2, [0.0_wp, yw], nrm, kf, .false., ws)
        f1 = 0.0_wp
        call surface_push(ws, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, m1, 0.0_wp, 2, blk, wdummy, &
                          gwdummy, nrm, hs, f1, imp1)
        v = v + hs*sum(f1(2, :))/mb            ! the rigid body: every node at v
        v1 = 0.0_wp
        v1(2, :) = v
        e = surface_step_energy(ws, nrm, [0.0_wp, u], v1, hs)
        eold = surface_energy(ws)
        w = w + imp1(2)*u
        q%xc(2, :) = q%xc(2, :) + hs*v
        yw = yw + hs*u
        g1 = q%xc(2, 1) - yw
        es = [0.5_wp*mb*v*v + e - w, 0.5_wp*mb*v*v + eold - w]
        if (was_on .and. g0 < 0.0_wp .and. g1 < 0.0_wp) then   ! behind over both steps
          big = max(big, abs(es(1) - prev(1)))
          old_change = max(old_change, abs(es(2) - prev(2)))
        end if
        was_on = g0 < 0.0_wp
        prev = es
        if (g0 > 0.0_wp .and. v > u) exit     ! thrown off, and clear of the wall
      end do
      lost = abs(es(1))/w
      worst = max(worst, lost)
      call check(g0 > 0.0_wp .and. v > u, 'phase '//itoa(nint(100*phases(ip)))// &
                 ' %: thrown off the wall')
      call check(lost <= wdt**2/8.0_wp, 'phase '//itoa(nint(100*phases(ip)))// &
                 ' %: after the bounce E within (omega dt)^2 / 8 of the work')
    end do
    call check(big <= 1.0e-10_wp*0.5_wp*mb*u*u, 'E constant to round-off while the point '// &
               'stays behind the wall')
    call check(old_change > 1.0e-2_wp*0.5_wp*mb*u*u, 'with the start-of-step energy it is not '// &
               '(the lag dt/2 f gdot)')
    print '(a, es9.2, a, es9.2, a, f7.4)', '  step energy: largest change in contact ', big, &
      '; start-of-step energy ', old_change, '; after the bounce |E| / W <= ', worst
    ! a particle's corner (linear basis) keeps 1/2 k g^2
    call two_squares(q)
    call surface_points(q, BASIS_LINEAR, [0.0_wp, 0.0_wp], nrm, kf, .false., ws)
    call grid_setup()
    call surface_push(ws, [-1.0_wp, -1.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, 2, &
                      reshape([0, 0, 1, 0], [2, 2]), reshape([(0.25_wp, it = 1, 8)], [4, 2]), &
                      reshape([(0.0_wp, it = 1, 16)], [2, 4, 2]), nrm, dt, force, imp)
    call check(ws%npt == 4 .and. all(ws%s(1:4) > 0.0_wp), 'linear: four corners pushed')
    call check_close(surface_step_energy(ws, nrm, [0.3_wp, -0.2_wp], vel, dt), &
                     surface_energy(ws), 'linear: the start-of-step energy', rtol=0.0_wp, &
                     atol=0.0_wp)
  end subroutine test_step_energy

  !> Friction on one point: stick stops the slip; Coulomb is bounded by mu lambda_n;
  !! mu = 0 changes nothing; the impulse is the momentum given.
  subroutine test_friction()
    real(wp) :: vc(2), lam_n, mom0(2), mom1(2), vt0
    call begin_test('friction: stick, coulomb bound, mu = 0')
    nodes = [1 + 1 + nx*1, 2 + 1 + nx*1, 1 + 1 + nx*2, 2 + 1 + nx*2]
    w4 = [0.7_wp, 0.3_wp, 0.0_wp, 0.0_wp]
    ! stick
    call grid_setup()
    call one_point([1.3_wp, 1.0_wp], -1.0e-3_wp, 2.0_wp)
    call surface_push(wk, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, 2, blk, wdummy, gwdummy, &
                      nrm, dt, force, imp)
    v0 = vel
    call surface_friction(wk, CONTACT_STICK, 0.0_wp, nrm, [0.5_wp, 0.0_wp], vel, dvel, imp)
    vc = matmul(vel(:, nodes), w4)
    call check_close(vc(1), 0.5_wp, 'stick: the point moves with the wall', rtol=1e-12_wp)
    call check_close(vel(2, :), v0(2, :), 'stick: normal velocities unchanged', atol=0.0_wp)
    mom0 = matmul(v0, mass)
    mom1 = matmul(vel, mass)
    call check_close(imp, mom1 - mom0, 'impulse = momentum given', rtol=1e-12_wp, atol=1e-15_wp)
    call check_close(reshape(dvel, [2*nn]), reshape(vel - v0, [2*nn]), 'dvel gets the same change', &
                     atol=1e-15_wp)
    ! coulomb with a small mu: the bound holds exactly, opposing the slip
    call grid_setup()
    call surface_push(wk, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, 2, blk, wdummy, gwdummy, &
                      nrm, dt, force, imp)
    lam_n = wk%lam(1, 1)
    v0 = vel
    vt0 = dot_product(matmul(v0(:, nodes), w4), [1.0_wp, 0.0_wp]) - 0.5_wp
    call surface_friction(wk, CONTACT_COULOMB, 1.0e-3_wp, nrm, [0.5_wp, 0.0_wp], vel, dvel, imp)
    call check_close(abs(imp(1)), 1.0e-3_wp*lam_n*sum(w4), 'coulomb: |lambda_t| = mu lambda_n', &
                     rtol=1e-12_wp)
    call check(imp(1)*vt0 < 0.0_wp, 'coulomb: friction opposes the slip')
    ! mu = 0: frictionless
    call grid_setup()
    call surface_push(wk, [0.0_wp, 0.0_wp], 1.0_wp, nx, ny, mass, 0.0_wp, 2, blk, wdummy, gwdummy, &
                      nrm, dt, force, imp)
    v0 = vel
    call surface_friction(wk, CONTACT_COULOMB, 0.0_wp, nrm, [0.5_wp, 0.0_wp], vel, dvel, imp)
    call check_close(reshape(vel, [2*nn]), reshape(v0, [2*nn]), &
                     'coulomb mu = 0: velocities unchanged', atol=0.0_wp)
    call check_close(imp, [0.0_wp, 0.0_wp], 'coulomb mu = 0: no impulse', atol=0.0_wp)
  end subroutine test_friction

end program test_contact
