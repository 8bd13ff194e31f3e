!> The CPDI2 wall contact on the surface curve (mpm_surface_curve) on a ring of domain corners
!! (r 24 / 26 mm, 4 through the wall, 96 around): the force is the gradient of the contact
!! energy (central difference in the wall position); the contact point moves continuously
!! along the surface as the wall turns (the corners' contact hops by a corner spacing), and
!! lies where the wall touches the circle; the curve first touches a wall where the circle
!! does (it passes through the corners: a wall touching the material surface pushes at once);
!! a half ring with its mirror plane has half the full ring's energy and force, to round-off.
! SPDX-License-Identifier: MIT
program test_surface_curve
  use mpm_kinds, only: wp
  use mpm_constants, only: pi, BASIS_CPDI2, SECTOR_FULL, SECTOR_HALF
  use mpm_particles, only: particles_t, particles_allocate, ring_counts, ring_fill
  use mpm_surface_contact, only: surface_work_t, surface_points, surface_energy
  use mpm_surface_curve, only: surface_curve_points
  use testing, only: begin_test, check, check_close, finish_tests
  use mpm_strings, only: itoa, rtoa
  implicit none
  real(wp), parameter :: kf = 1.0e6_wp         ! stiffness per unit point mass [1/s^2]
  real(wp), parameter :: ri = 0.024_wp, ro = 0.026_wp, cen(2) = [0.0_wp, 0.026_wp]
  integer, parameter :: nkf = 96               ! particles around the full ring
  real(wp) :: none(4, 0), mirror(4, 1), nrm(2), xw(2), d, eps, ep, em, f, fh, eh, ef
  real(wp) :: sag, theta, dth, phi_c, phi_prev, jump, jump_c, off, xc(2)
  real(wp) :: gall
  integer :: i, k, j, bad
  type(particles_t) :: full, half, sheared
  type(surface_work_t) :: wk

  call ring(full, SECTOR_FULL)
  call ring(half, SECTOR_HALF)
  sheared = full                               ! an affine map of the ring: nothing folds
  sheared%xc(1, :) = 1.2_wp*full%xc(1, :) + 0.3_wp*full%xc(2, :)
  sheared%xc(2, :) = 0.8_wp*full%xc(2, :)
  nrm = [0.0_wp, 1.0_wp]

  ! the chords between corners lie inside the corners' circle by up to r dth^2 / 8 (14 um);
  ! the curve, whose control points are shifted out by an eighth of the corners' second
  ! difference, passes through the corners and lies on the circle between them
  dth = 2.0_wp*pi/real(nkf, wp)              ! the corner spacing in angle
  sag = ro*dth**2/8.0_wp

  ! the wall's first contact, as it turns over a corner spacing: the depth of the plane
  ! (distance from the centre ro - d) at which the curve's energy starts, by bisection, is
  ! the circle's, d = 0, within 2 % of the chord's sag (the B-spline of the corners lies
  ! inside the circle by a sag, at the corners and between them: a wall touching the
  ! material surface at t = 0 would push only after moving that far)
  call begin_test('the curve touches a wall where the circle does')
  off = 0.0_wp
  do i = 0, 10
    theta = dth*real(i, wp)/10.0_wp
    nrm = [sin(theta), cos(theta)]
    off = max(off, abs(onset_depth(nrm)))
  end do
  call check(off < 0.02_wp*sag, 'first contact within 2 % of the sag r dth^2 / 8 of the '// &
             'circle, at every wall angle over a spacing (largest '//rtoa(off/sag)//' sag)')
  nrm = [0.0_wp, 1.0_wp]

  call begin_test('the force is the gradient of the energy')
  eps = 1.0e-9_wp
  do k = 1, 3
    d = sag + 1.0e-5_wp*4.0_wp**(k - 1)      ! 10, 40, 160 um behind the wall
    call surface_curve_points(full, [0.0_wp, d], nrm, kf, none, 1.0e-9_wp, wk)
    f = sum(wk%fn(1:wk%npt))
    call surface_curve_points(full, [0.0_wp, d + eps], nrm, kf, none, 1.0e-9_wp, wk)
    ep = surface_energy(wk)
    call surface_curve_points(full, [0.0_wp, d - eps], nrm, kf, none, 1.0e-9_wp, wk)
    em = surface_energy(wk)
    call check(f > 0.0_wp, 'a force')
    call check_close(f, (ep - em)/(2.0_wp*eps), 'sum of the point forces = dE/d(wall '// &
                     'position) (central difference, 1e-6)', rtol=1.0e-6_wp)
  end do

  call begin_test('the contact point moves continuously as the wall turns')
  d = sag + 1.0e-7_wp                        ! depth behind the wall
  jump = 0.0_wp
  jump_c = 0.0_wp
  off = 0.0_wp
  do i = 0, 300
    theta = 3.0_wp*dth*real(i, wp)/300.0_wp + 0.01_wp*dth
    nrm = [sin(theta), cos(theta)]           ! the wall touches the circle at angle -theta
    xw = cen - (ro - d)*nrm
    call surface_curve_points(full, xw, nrm, kf, none, 1.0e-9_wp, wk)
    phi_c = contact_angle()
    off = max(off, abs(phi_c + theta))
    if (i > 0) jump = max(jump, abs(phi_c - phi_prev))
    phi_prev = phi_c
  end do
  call check(jump < 0.05_wp*dth, 'curve: the contact point moves by under 5 % of a '// &
             'corner spacing per 1 % of a spacing of turn')
  call check(off < 0.05_wp*dth, 'curve: the contact point is where the wall touches the '// &
             'circle, within 5 % of a corner spacing')
  do i = 0, 300                              ! the same with the corners: hops
    theta = 3.0_wp*dth*real(i, wp)/300.0_wp + 0.01_wp*dth
    nrm = [sin(theta), cos(theta)]
    xw = cen - (ro - 1.05_wp*sag)*nrm      ! a corner or two behind the wall
    call surface_points(full, BASIS_CPDI2, xw, nrm, kf, .false., wk)
    phi_c = contact_angle()
    if (i > 0) jump_c = max(jump_c, abs(phi_c - phi_prev))
    phi_prev = phi_c
  end do
  call check(jump_c > 0.25_wp*dth, 'corners: the contact hops by over a quarter of a spacing '// &
             '(what the curve removes)')
  print '(a,3f8.4)', '  largest step of the contact point / corner spacing (curve, corners), '// &
    'offset:', jump/dth, jump_c/dth, off/dth

  call begin_test('a half ring with its mirror plane: half the full ring''s contact')
  mirror(:, 1) = [0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp]
  nrm = [0.0_wp, 1.0_wp]
  do k = 1, 2
    d = sag + 1.0e-5_wp*10.0_wp**(k - 1)
    call surface_curve_points(full, [0.0_wp, d], nrm, kf, none, 1.0e-9_wp, wk)
    ef = surface_energy(wk)
    f = sum(wk%fn(1:wk%npt))
    call surface_curve_points(half, [0.0_wp, d], nrm, kf, mirror, 1.0e-9_wp, wk)
    eh = surface_energy(wk)
    fh = sum(wk%fn(1:wk%npt))
    call check_close(eh, 0.5_wp*ef, 'energy of the half = half the full ring''s', rtol=1.0e-12_wp)
    call check_close(fh, 0.5_wp*f, 'force of the half = half the full ring''s', rtol=1.0e-12_wp)
  end do

  ! the scan reads the boundary corners only: its deepest gap (the check that stops a run whose
  ! material passed a wall) must be the deepest of all corners, on the full and the half ring
  ! and on a sheared copy, for walls all round at depths from a wall thickness to beyond a
  ! diameter
  call begin_test('the deepest gap over the boundary corners is the deepest of all corners')
  bad = 0
  do k = 1, 3
    do i = 0, 71
      theta = 2.0_wp*pi*real(i, wp)/72.0_wp
      nrm = [sin(theta), cos(theta)]
      do j = 1, 4
        xw = cen - (ro - 0.002_wp*3.0_wp**(j - 1))*nrm   ! 2, 6, 18, 54 mm into the ring
        select case (k)
        case (1)
          call surface_curve_points(full, xw, nrm, kf, none, 1.0e-9_wp, wk)
          gall = min(0.0_wp, minval(matmul(nrm, full%xc) - dot_product(xw, nrm)))
        case (2)
          call surface_curve_points(half, xw, nrm, kf, mirror, 1.0e-9_wp, wk)
          gall = min(0.0_wp, minval(matmul(nrm, half%xc) - dot_product(xw, nrm)))
        case default
          call surface_curve_points(sheared, xw, nrm, kf, none, 1.0e-9_wp, wk)
          gall = min(0.0_wp, minval(matmul(nrm, sheared%xc) - dot_product(xw, nrm)))
        end select
        if (abs(wk%gmin - gall) > 1.0e-15_wp) bad = bad + 1
      end do
    end do
  end do
  call check(bad == 0, '3 x 72 x 4 walls: '//itoa(bad)//' with another deepest gap (1e-15 m)')

  call finish_tests('test_surface_curve')

contains

  !> Depth d of the plane with unit normal nrm, at distance ro - d from the centre, at which
  !! the full ring's curve first has energy [m] (bisection between -3 and 3 sag).
  function onset_depth(nrm) result(dd)
    real(wp), intent(in) :: nrm(2)
    real(wp) :: dd, lo, hi
    integer :: it
    lo = -3.0_wp*sag
    hi = 3.0_wp*sag
    do it = 1, 60
      dd = 0.5_wp*(lo + hi)
      call surface_curve_points(full, cen - (ro - dd)*nrm, nrm, kf, none, 1.0e-9_wp, wk)
      if (surface_energy(wk) > 0.0_wp) then
        hi = dd
      else
        lo = dd
      end if
    end do
    dd = 0.5_wp*(lo + hi)
  end function onset_depth

  !> Ring of CPDI2 corners, centre cen, of sector `sector`.
  subroutine ring(p, sector)
    type(particles_t), intent(inout) :: p
    integer, intent(in) :: sector
    integer :: nk, np, nc
    call ring_counts(ri, ro, 4, nkf, sector, nk, np, nc)
    call particles_allocate(p, np, nc)
    call ring_fill(p, 0, 0, cen, ri, ro, 4, nk, sector, 7800.0_wp, [0.0_wp, 0.0_wp], 1, 1)
  end subroutine ring

  !> Angle (from straight down) of the force-weighted centre of the points in wk.
  real(wp) function contact_angle() result(a)
    integer :: j
    xc = 0.0_wp
    do j = 1, wk%npt
      xc = xc + wk%fn(j)*pos(j)
    end do
    xc = xc/sum(wk%fn(1:wk%npt)) - cen
    a = atan2(xc(1), -xc(2))
  end function contact_angle

  !> Position of point j: the curve point, or the corner.
  function pos(j) result(x)
    integer, intent(in) :: j
    real(wp) :: x(2)
    if (wk%curve) then
      x = wk%xs(:, j)
    else
      x = full%xc(:, -wk%owner(j))
    end if
  end function pos

end program test_surface_curve
