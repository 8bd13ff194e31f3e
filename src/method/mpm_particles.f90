!> Material points as a structure of arrays, and the bodies that create them (rings, rectangles).
! SPDX-License-Identifier: MIT
!
! Every particle is a quadrilateral domain. Ring particles (docs/input.md, &body): radii
! r_j = r_in + j t / n_t, angles theta_k; particle (j, k) has the corners (r_j, theta_k),
! (r_j+1, theta_k), (r_j+1, theta_k+1), (r_j, theta_k+1), counter-clockwise. The corners are
! stored once and shared by neighbours (CPDI2 keeps the tiling conforming); the other bases
! use the domain's centroid, area and (CPDI1) half-vectors.
module mpm_particles
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: pi, SECTOR_FULL, SECTOR_HALF, SECTOR_QUARTER, BASIS_CPDI1, BASIS_CPDI2, &
                           BASIS_LINEAR
  implicit none
  private
  public :: particles_t, particles_allocate, ring_counts, ring_fill, rect_counts, rect_fill, &
            quads_fill, &
            quad_area_centroid, particles_memory_bytes, particles_write, particles_read, &
            particle_corners, particles_copy, basis_reach, basis_block, corner_gaps

  !> All particles of all bodies. Component index first.
  type :: particles_t
    integer :: np = 0                      !! number of particles
    integer :: nc = 0                      !! number of domain corners
    real(wp), allocatable :: x(:,:)        !! position (2, np) [m]
    real(wp), allocatable :: v(:,:)        !! velocity (2, np) [m/s]
    real(wp), allocatable :: mass(:)       !! mass per unit depth [kg/m]
    real(wp), allocatable :: vol0(:)       !! initial area (volume per unit depth) [m^2]
    real(wp), allocatable :: vol(:)        !! current area J * vol0 [m^2]
    real(wp), allocatable :: F(:,:,:)      !! deformation gradient (2, 2, np) [-]
    real(wp), allocatable :: stress(:,:)   !! Cauchy stress (xx, yy, xy, zz) (4, np) [Pa]
    real(wp), allocatable :: eqps(:)       !! equivalent plastic strain [-]
    real(wp), allocatable :: wplastic(:)   !! plastic work per unit depth [J/m]
    real(wp), allocatable :: r10(:,:)      !! initial CPDI1 half-vector 1 (2, np) [m]
    real(wp), allocatable :: r20(:,:)      !! initial CPDI1 half-vector 2 (2, np) [m]
    real(wp), allocatable :: half(:,:)     !! uGIMP / linear half sizes (2, np) [m]
    integer, allocatable :: corner(:,:)    !! corner ids (4, np), counter-clockwise
    real(wp), allocatable :: xc(:,:)       !! corner positions (2, nc) [m]
    integer, allocatable :: mat(:)         !! material index
    integer, allocatable :: body(:)        !! body index
  end type particles_t

contains

  !> Allocate storage for np particles and nc corners; zero the state, F = I.
  subroutine particles_allocate(p, np, nc)
    type(particles_t), intent(inout) :: p  !! particles
    integer, intent(in) :: np              !! number of particles
    integer, intent(in) :: nc              !! number of corners
    p%np = np
    p%nc = nc
    allocate(p%x(2, np), p%v(2, np), p%mass(np), p%vol0(np), p%vol(np), p%F(2, 2, np))
    allocate(p%stress(4, np), p%eqps(np), p%wplastic(np), p%r10(2, np), p%r20(2, np))
    allocate(p%half(2, np), p%corner(4, np), p%xc(2, nc), p%mat(np), p%body(np))
    p%x = 0.0_wp; p%v = 0.0_wp; p%mass = 0.0_wp; p%vol0 = 0.0_wp; p%vol = 0.0_wp
    p%F = 0.0_wp
    p%F(1, 1, :) = 1.0_wp
    p%F(2, 2, :) = 1.0_wp
    p%stress = 0.0_wp; p%eqps = 0.0_wp; p%wplastic = 0.0_wp
    p%r10 = 0.0_wp; p%r20 = 0.0_wp; p%half = 0.0_wp; p%corner = 0; p%xc = 0.0_wp
    p%mat = 0; p%body = 0
  end subroutine particles_allocate

  !> Angular span and particle/corner counts of a ring body.
  pure subroutine ring_counts(r_inner, r_outer, n_thick, n_circ, sector, nk, np, nc)
    real(wp), intent(in) :: r_inner, r_outer  !! radii [m]
    integer, intent(in) :: n_thick            !! particles through the wall
    integer, intent(in) :: n_circ             !! particles around the whole ring (0 = auto)
    integer, intent(in) :: sector             !! SECTOR_* code
    integer, intent(out) :: nk                !! particles around the modelled sector
    integer, intent(out) :: np                !! particles
    integer, intent(out) :: nc                !! corners
    integer :: n_full, parts
    parts = 1
    if (sector == SECTOR_HALF) parts = 2
    if (sector == SECTOR_QUARTER) parts = 4
    n_full = n_circ
    if (n_full <= 0) then   ! aspect ratio near 1 at the mid-surface, divisible by 4
      n_full = max(4, 4*nint(2.0_wp*pi*0.5_wp*(r_inner + r_outer) &
                    /((r_outer - r_inner)/real(n_thick, wp))/4.0_wp))
    end if
    nk = n_full/parts
    np = n_thick*nk
    if (sector == SECTOR_FULL) then
      nc = (n_thick + 1)*nk
    else
      nc = (n_thick + 1)*(nk + 1)
    end if
  end subroutine ring_counts

  !> Fill particles ip0+1.. and corners ic0+1.. of a ring (the layout in the header above).
  !! half: the part x >= cx; quarter: x >= cx and y >= cy.
  subroutine ring_fill(p, ip0, ic0, center, r_inner, r_outer, n_thick, nk, sector, rho, &
                       velocity, imat, ibody)
    type(particles_t), intent(inout) :: p     !! particles
    integer, intent(in) :: ip0, ic0           !! particles and corners already filled
    real(wp), intent(in) :: center(2)         !! ring centre [m]
    real(wp), intent(in) :: r_inner, r_outer  !! radii [m]
    integer, intent(in) :: n_thick, nk        !! particles through the wall and around
    integer, intent(in) :: sector             !! SECTOR_* code
    real(wp), intent(in) :: rho               !! density (mass-scaled) [kg/m^3]
    real(wp), intent(in) :: velocity(2)       !! initial velocity [m/s]
    integer, intent(in) :: imat, ibody        !! material and body index
    integer :: j, k, ip, kc, nkc
    real(wp) :: theta0, dtheta, r, th, xq(2, 4)
    theta0 = 0.0_wp
    dtheta = 2.0_wp*pi/real(nk, wp)
    nkc = nk
    select case (sector)
    case (SECTOR_HALF)
      theta0 = -0.5_wp*pi; dtheta = pi/real(nk, wp); nkc = nk + 1
    case (SECTOR_QUARTER)
      theta0 = 0.0_wp; dtheta = 0.5_wp*pi/real(nk, wp); nkc = nk + 1
    end select
    do k = 0, nkc - 1
      th = theta0 + dtheta*real(k, wp)
      do j = 0, n_thick
        r = r_inner + (r_outer - r_inner)*real(j, wp)/real(n_thick, wp)
        p%xc(:, ic0 + 1 + j + (n_thick + 1)*k) = center + r*[cos(th), sin(th)]
      end do
    end do
    do k = 0, nk - 1
      kc = k + 1
      if (kc == nkc) kc = 0                   ! the full ring closes on itself
      do j = 0, n_thick - 1
        ip = ip0 + 1 + j + n_thick*k
        p%corner(:, ip) = ic0 + [1 + j + (n_thick + 1)*k, 2 + j + (n_thick + 1)*k, &
                                 2 + j + (n_thick + 1)*kc, 1 + j + (n_thick + 1)*kc]
        xq = p%xc(:, p%corner(:, ip))
        call set_particle(p, ip, xq, rho, velocity, imat, ibody)
      end do
    end do
  end subroutine ring_fill

  !> Particle and corner counts of a rectangle.
  pure subroutine rect_counts(n_x, n_y, np, nc)
    integer, intent(in) :: n_x, n_y           !! particles along x and y
    integer, intent(out) :: np, nc            !! particles and corners
    np = n_x*n_y
    nc = (n_x + 1)*(n_y + 1)
  end subroutine rect_counts

  !> Fill particles ip0+1.. and corners ic0+1.. of an axis-aligned rectangle.
  subroutine rect_fill(p, ip0, ic0, center, size, n_x, n_y, rho, velocity, imat, ibody)
    type(particles_t), intent(inout) :: p     !! particles
    integer, intent(in) :: ip0, ic0           !! particles and corners already filled
    real(wp), intent(in) :: center(2)         !! rectangle centre [m]
    real(wp), intent(in) :: size(2)           !! side lengths [m]
    integer, intent(in) :: n_x, n_y           !! particles along x and y
    real(wp), intent(in) :: rho               !! density (mass-scaled) [kg/m^3]
    real(wp), intent(in) :: velocity(2)       !! initial velocity [m/s]
    integer, intent(in) :: imat, ibody        !! material and body index
    integer :: i, j, ip
    real(wp) :: lo(2), xq(2, 4)
    lo = center - 0.5_wp*size
    do j = 0, n_y
      do i = 0, n_x
        p%xc(:, ic0 + 1 + i + (n_x + 1)*j) = lo + size*[real(i, wp)/real(n_x, wp), &
                                                          real(j, wp)/real(n_y, wp)]
      end do
    end do
    do j = 0, n_y - 1
      do i = 0, n_x - 1
        ip = ip0 + 1 + i + n_x*j
        p%corner(:, ip) = ic0 + [1 + i + (n_x + 1)*j, 2 + i + (n_x + 1)*j, &
                                 2 + i + (n_x + 1)*(j + 1), 1 + i + (n_x + 1)*(j + 1)]
        xq = p%xc(:, p%corner(:, ip))
        call set_particle(p, ip, xq, rho, velocity, imat, ibody)
      end do
    end do
  end subroutine rect_fill

  !> Fill particles ip0+1.. and corners ic0+1.. from given quadrilaterals (mpm_sections).
  subroutine quads_fill(p, ip0, ic0, xc, quad, rho, velocity, imat, ibody)
    type(particles_t), intent(inout) :: p     !! particles
    integer, intent(in) :: ip0, ic0           !! particles and corners already filled
    real(wp), intent(in) :: xc(:,:)           !! corners (2, nc) [m]
    integer, intent(in) :: quad(:,:)          !! corners of each particle, counter-clockwise
    real(wp), intent(in) :: rho               !! density (mass-scaled) [kg/m^3]
    real(wp), intent(in) :: velocity(2)       !! initial velocity [m/s]
    integer, intent(in) :: imat, ibody        !! material and body index
    integer :: k
    p%xc(:, ic0 + 1:ic0 + size(xc, 2)) = xc
    do k = 1, size(quad, 2)
      p%corner(:, ip0 + k) = ic0 + quad(:, k)
      call set_particle(p, ip0 + k, xc(:, quad(:, k)), rho, velocity, imat, ibody)
    end do
  end subroutine quads_fill

  !> Initial state of one particle from its quadrilateral.
  subroutine set_particle(p, ip, xq, rho, velocity, imat, ibody)
    type(particles_t), intent(inout) :: p     !! particles
    integer, intent(in) :: ip                 !! particle index
    real(wp), intent(in) :: xq(2, 4)          !! corners, counter-clockwise [m]
    real(wp), intent(in) :: rho               !! density [kg/m^3]
    real(wp), intent(in) :: velocity(2)       !! [m/s]
    integer, intent(in) :: imat, ibody        !! material and body index
    real(wp) :: area, c(2)
    call quad_area_centroid(xq, area, c)
    p%x(:, ip) = c
    p%v(:, ip) = velocity
    p%vol0(ip) = area
    p%vol(ip) = area
    p%mass(ip) = rho*area
    ! CPDI1 parallelogram: mean edge vectors (exact for parallelograms and isosceles trapezia)
    p%r10(:, ip) = 0.25_wp*(xq(:, 2) - xq(:, 1) + xq(:, 3) - xq(:, 4))
    p%r20(:, ip) = 0.25_wp*(xq(:, 4) - xq(:, 1) + xq(:, 3) - xq(:, 2))
    p%half(:, ip) = 0.5_wp*sqrt(area)          ! uGIMP square of side sqrt(V0), docs/method.md
    p%mat(ip) = imat
    p%body(ip) = ibody
  end subroutine set_particle

  !> Area (shoelace, positive counter-clockwise) and area centroid of a quadrilateral.
  pure subroutine quad_area_centroid(xq, area, c)
    real(wp), intent(in) :: xq(2, 4)          !! corners [m]
    real(wp), intent(out) :: area             !! signed area [m^2]
    real(wp), intent(out) :: c(2)             !! centroid [m]
    real(wp) :: cr(4), s(2)
    ! edge a from corner a to corner a + 1 (4 to 1), summed in that order
    cr(1) = xq(1, 1)*xq(2, 2) - xq(1, 2)*xq(2, 1)
    cr(2) = xq(1, 2)*xq(2, 3) - xq(1, 3)*xq(2, 2)
    cr(3) = xq(1, 3)*xq(2, 4) - xq(1, 4)*xq(2, 3)
    cr(4) = xq(1, 4)*xq(2, 1) - xq(1, 1)*xq(2, 4)
    area = 0.0_wp + cr(1) + cr(2) + cr(3) + cr(4)
    s = 0.0_wp + (xq(:, 1) + xq(:, 2))*cr(1)
    s = s + (xq(:, 2) + xq(:, 3))*cr(2)
    s = s + (xq(:, 3) + xq(:, 4))*cr(3)
    s = s + (xq(:, 4) + xq(:, 1))*cr(4)
    area = 0.5_wp*area
    c = s/(6.0_wp*area)
  end subroutine quad_area_centroid

  !> Memory held by the particle arrays [bytes] (excluding the per-step basis cache).
  pure function particles_memory_bytes(p) result(b)
    type(particles_t), intent(in) :: p        !! particles
    integer(i8) :: b
    b = (bytes_r(p%x) + bytes_r(p%v) + bytes_r(p%r10) + bytes_r(p%r20) + bytes_r(p%half) &
         + bytes_r(p%stress) + bytes_r(p%xc)) + (bytes_1(p%mass) + bytes_1(p%vol0) &
         + bytes_1(p%vol) + bytes_1(p%eqps) + bytes_1(p%wplastic)) + 8_i8*size(p%F, kind=i8) &
        + 4_i8*(size(p%corner, kind=i8) + size(p%mat, kind=i8) + size(p%body, kind=i8))
  contains
    pure integer(i8) function bytes_r(a)
      real(wp), intent(in) :: a(:,:)
      bytes_r = int(storage_size(a)/8, i8)*size(a, kind=i8)
    end function bytes_r
    pure integer(i8) function bytes_1(a)
      real(wp), intent(in) :: a(:)
      bytes_1 = int(storage_size(a)/8, i8)*size(a, kind=i8)
    end function bytes_1
  end function particles_memory_bytes

  !> The four corners of particle ip's domain for basis `basis`, counter-clockwise [m]: the
  !! shared CPDI2 corners; the CPDI1 parallelogram x -+ r1 -+ r2 with r = F r0; otherwise
  !! (linear, uGIMP) the axis-aligned square x -+ half, or with `deformed` the half sizes
  !! carried by F, x -+ F(:,1) half(1) -+ F(:,2) half(2) (the contact between bodies). The one
  !! answer to "where is this particle's material" (wall gaps, output, contact; the basis step
  !! gathers CPDI2 corners inline).
  pure function particle_corners(p, ip, basis, deformed) result(xq)
    type(particles_t), intent(in) :: p        !! particles
    integer, intent(in) :: ip                 !! particle
    integer, intent(in) :: basis              !! BASIS_* code
    logical, intent(in), optional :: deformed !! linear, uGIMP: the domain carried by F
    real(wp) :: xq(2, 4)
    real(wp) :: r(2, 2, 1)
    logical :: carried
    carried = .false.
    if (present(deformed)) carried = deformed
    if (basis == BASIS_CPDI2) then
      xq(:, 1) = p%xc(:, p%corner(1, ip))
      xq(:, 2) = p%xc(:, p%corner(2, ip))
      xq(:, 3) = p%xc(:, p%corner(3, ip))
      xq(:, 4) = p%xc(:, p%corner(4, ip))
      return
    end if
    call domain_vectors(ip, ip, p%np, basis, carried, p%F, p%half, p%r10, p%r20, r)
    xq(:, 1) = p%x(:, ip) - r(:, 1, 1) - r(:, 2, 1)
    xq(:, 2) = p%x(:, ip) + r(:, 1, 1) - r(:, 2, 1)
    xq(:, 3) = p%x(:, ip) + r(:, 1, 1) + r(:, 2, 1)
    xq(:, 4) = p%x(:, ip) - r(:, 1, 1) + r(:, 2, 1)
  end function particle_corners

  !> The half-vectors of the domains x -+ r1 -+ r2 of particles ip0..ip1 of the bases linear,
  !! uGIMP and CPDI1 (CPDI2's domain is its shared corners): CPDI1 F r10 and F r20; the others
  !! the half sizes along x and y, carried by F when `carried`. A range, so that a scan pays one
  !! call per chunk, not per particle.
  pure subroutine domain_vectors(ip0, ip1, np, basis, carried, F, half, r10, r20, r)
    integer, intent(in) :: ip0, ip1           !! particle range [-]
    integer, intent(in) :: np                 !! particles [-]
    integer, intent(in) :: basis              !! BASIS_* code (not CPDI2)
    logical, intent(in) :: carried            !! linear, uGIMP: the domain carried by F
    real(wp), intent(in) :: F(2, 2, np)       !! deformation gradients [-]
    real(wp), intent(in) :: half(2, np)       !! half sizes at t = 0 [m]
    real(wp), intent(in) :: r10(2, np), r20(2, np)  !! CPDI1 half-vectors at t = 0 [m]
    real(wp), intent(out) :: r(2, 2, ip0:ip1) !! r1 = r(:, 1, ip), r2 = r(:, 2, ip) now [m]
    integer :: ip
    if (basis == BASIS_CPDI1) then
      do ip = ip0, ip1
        r(:, 1, ip) = F(:, 1, ip)*r10(1, ip) + F(:, 2, ip)*r10(2, ip)   ! F r10, as matmul sums
        r(:, 2, ip) = F(:, 1, ip)*r20(1, ip) + F(:, 2, ip)*r20(2, ip)
      end do
    else if (carried) then
      do ip = ip0, ip1
        r(:, 1, ip) = F(:, 1, ip)*half(1, ip)
        r(:, 2, ip) = F(:, 2, ip)*half(2, ip)
      end do
    else
      do ip = ip0, ip1
        r(:, 1, ip) = [half(1, ip), 0.0_wp]
        r(:, 2, ip) = [0.0_wp, half(2, ip)]
      end do
    end if
  end subroutine domain_vectors

  !> The deepest gap to the plane through xw (unit normal `normal`) of the corners of the
  !! deformed domains (particle_corners, deformed) of particles ip0..ip1 of the bases linear,
  !! uGIMP and CPDI1, in dmin, merged into gmin; dmin = 1 for a particle whose corners are surely
  !! clear of the plane, which is skipped: the deepest corner x -+ r1 -+ r2 lies at the gap
  !! d0 - |r1.n| - |r2.n|, and a particle is skipped when that is positive by more than 1e-12
  !! of the magnitudes |x|, |xw|, |r1|, |r2| (the corners' own gaps round at about 1e-15 of
  !! them; r1, r2 are the same numbers as particle_corners'), so that no bit of what the wall
  !! contact gathers changes (tests/test_contact.f90). Explicit shapes: the scan reads the
  !! arrays without descriptors.
  subroutine corner_gaps(p, ip0, ip1, basis, np, x, F, half, r10, r20, xw, normal, dmin, gmin)
    type(particles_t), intent(in) :: p     !! particles (the corners of those not skipped)
    integer, intent(in) :: ip0, ip1        !! particle range [-]
    integer, intent(in) :: basis           !! BASIS_* code (linear, uGIMP, CPDI1)
    integer, intent(in) :: np              !! particles [-]
    real(wp), intent(in) :: x(2, np)       !! positions [m]
    real(wp), intent(in) :: F(2, 2, np)    !! deformation gradients [-]
    real(wp), intent(in) :: half(2, np)    !! half sizes at t = 0 [m]
    real(wp), intent(in) :: r10(2, np), r20(2, np)  !! CPDI1 half-vectors at t = 0 [m]
    real(wp), intent(in) :: xw(2)          !! a point on the plane [m]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(inout) :: dmin(np)    !! deepest corner gap of each particle [m]
    real(wp), intent(inout) :: gmin        !! deepest of all (<= 0) [m]
    real(wp) :: r1(2), r2(2), d0, mag, xq(2, 4), r(2, 2, ip0:ip1)
    integer :: ip, a
    call domain_vectors(ip0, ip1, np, basis, .true., F, half, r10, r20, r)
    do ip = ip0, ip1
      r1 = r(:, 1, ip)
      r2 = r(:, 2, ip)
      d0 = (x(1, ip) - xw(1))*normal(1) + (x(2, ip) - xw(2))*normal(2)
      mag = abs(x(1, ip)) + abs(x(2, ip)) + abs(xw(1)) + abs(xw(2)) + abs(r1(1)) + &
            abs(r1(2)) + abs(r2(1)) + abs(r2(2))
      if (d0 - abs(r1(1)*normal(1) + r1(2)*normal(2)) - abs(r2(1)*normal(1) + &
          r2(2)*normal(2)) > 1.0e-12_wp*mag) then
        dmin(ip) = 1.0_wp                  ! most particles: no corner near the plane
        cycle
      end if
      xq = particle_corners(p, ip, basis, deformed=.true.)
      dmin(ip) = minval([(dot_product(xq(:, a) - xw, normal), a = 1, 4)])
      gmin = min(gmin, dmin(ip))
    end do
  end subroutine corner_gaps

  !> How far the basis reaches beyond the particles' domain corners, given their largest half
  !! size [m]: the fitted grid's margin beyond two cells (mpm_setup from the particles,
  !! mpm_budget from the input's estimate). The half size for the bases whose particle is a
  !! domain (uGIMP, CPDI1, CPDI2), 0 for linear (its particle is a point).
  pure real(wp) function basis_reach(basis, half_max) result(reach)
    integer, intent(in) :: basis              !! BASIS_* code
    real(wp), intent(in) :: half_max          !! largest particle half size [m]
    reach = 0.0_wp
    if (basis /= BASIS_LINEAR) reach = half_max
  end function basis_reach

  !> Nodes per direction of a particle's block of weights: 2 for the linear basis (its particle
  !! is a point: the 4 nodes of its cell), else the support of a domain `ext` across (the
  !! domain and a cell each side), at least 3. mpm_weights starts from the smallest (ext = 0)
  !! and widens the blocks when domains grow; mpm_budget estimates it from the input.
  pure integer function basis_block(basis, ext, h) result(nb)
    integer, intent(in) :: basis              !! BASIS_* code
    real(wp), intent(in) :: ext               !! largest domain extent [m]
    real(wp), intent(in) :: h                 !! cell size [m]
    nb = 2
    if (basis == BASIS_LINEAR) return
    nb = 3                                    ! (ext = 0, or not a number: no division)
    if (ext > 0.0_wp) nb = 2 + max(1, ceiling(min(ext/h, 1.0e6_wp)))
  end function basis_block

  !> dst = src, reusing dst's arrays when they have the sizes already (the driver copies the
  !! particles every few steps as the last good state: no allocation each time).
  subroutine particles_copy(dst, src)
    type(particles_t), intent(inout) :: dst   !! the copy
    type(particles_t), intent(in) :: src      !! the particles
    if (.not. allocated(dst%x) .or. dst%np /= src%np .or. dst%nc /= src%nc) then
      dst = src
      return
    end if
    call copy_reals(size(src%x), src%x, dst%x)     ! (as flat arrays: `dst%x(:, :) = src%x`
    call copy_reals(size(src%v), src%v, dst%v)     ! was an element loop per dimension)
    call copy_reals(src%np, src%mass, dst%mass)
    call copy_reals(src%np, src%vol0, dst%vol0)
    call copy_reals(src%np, src%vol, dst%vol)
    call copy_reals(size(src%F), src%F, dst%F)
    call copy_reals(size(src%stress), src%stress, dst%stress)
    call copy_reals(src%np, src%eqps, dst%eqps)
    call copy_reals(src%np, src%wplastic, dst%wplastic)
    call copy_reals(size(src%r10), src%r10, dst%r10)
    call copy_reals(size(src%r20), src%r20, dst%r20)
    call copy_reals(size(src%half), src%half, dst%half)
    call copy_integers(size(src%corner), src%corner, dst%corner)
    call copy_reals(size(src%xc), src%xc, dst%xc)
    call copy_integers(src%np, src%mat, dst%mat)
    call copy_integers(src%np, src%body, dst%body)
  end subroutine particles_copy

  !> b = a for n reals (particles_copy: contiguous arrays of any rank as flat ones).
  pure subroutine copy_reals(n, a, b)
    integer, intent(in) :: n                  !! elements
    real(wp), intent(in) :: a(n)              !! source
    real(wp), intent(out) :: b(n)             !! copy
    b = a
  end subroutine copy_reals

  !> b = a for n integers (particles_copy).
  pure subroutine copy_integers(n, a, b)
    integer, intent(in) :: n                  !! elements
    integer, intent(in) :: a(n)               !! source
    integer, intent(out) :: b(n)              !! copy
    b = a
  end subroutine copy_integers

  !> Write every particle array to the open unformatted stream unit u (a checkpoint record:
  !! the counts, then the arrays).
  subroutine particles_write(p, u, stat, errmsg)
    type(particles_t), intent(in) :: p        !! particles
    integer, intent(in) :: u                  !! unit, open for unformatted stream output
    integer, intent(out) :: stat              !! 0 or the iostat of the failed write
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    write(u, iostat=stat, iomsg=errmsg) p%np, p%nc
    if (stat == 0) write(u, iostat=stat, iomsg=errmsg) p%x, p%v, p%mass, p%vol0, p%vol, p%F, &
      p%stress, p%eqps, p%wplastic, p%r10, p%r20, p%half, p%corner, p%xc, p%mat, p%body
  end subroutine particles_write

  !> Read a record of particles_write into p, which must hold as many particles and corners
  !! (stat = -1 when the counts differ; p is then unchanged).
  subroutine particles_read(p, u, stat, errmsg)
    type(particles_t), intent(inout) :: p     !! particles, allocated to the stored counts
    integer, intent(in) :: u                  !! unit, open for unformatted stream input
    integer, intent(out) :: stat              !! 0, -1 (other counts) or the iostat of the read
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    integer :: np, nc
    read(u, iostat=stat, iomsg=errmsg) np, nc
    if (stat /= 0) return
    if (np /= p%np .or. nc /= p%nc) then
      stat = -1
      return
    end if
    read(u, iostat=stat, iomsg=errmsg) p%x, p%v, p%mass, p%vol0, p%vol, p%F, p%stress, p%eqps, &
      p%wplastic, p%r10, p%r20, p%half, p%corner, p%xc, p%mat, p%body
  end subroutine particles_read
end module mpm_particles
