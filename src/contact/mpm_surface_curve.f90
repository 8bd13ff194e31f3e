!> CPDI2 wall contact on a smooth surface curve: the penalty of mpm_surface_contact integrated
!! along a quadratic B-spline through the boundary's domain corners, so that the contact moves
!! continuously along the surface instead of hopping from corner to corner.
! SPDX-License-Identifier: MIT
!
! Why: a curved surface made of corners touches a plane at one corner at a time. In the ring
! crush the contact is a line that travels outwards along the ring as the ring flattens (the
! middle lifts off), so with corner contact the whole platen force sits on one or two corners
! and jumps to the next corner every time the surface has rolled by one corner spacing: at
! h = t/4, n_t 8, aspect 2 the load changed corner every 0.68 mm of approach, the period of
! the force oscillation of the study (2.4 % RMS of the mean force; docs/validation.md).
!
! The curve: the boundary edges of the body (an edge of one particle only; the corners are
! counter-clockwise, so an edge a -> b is on the boundary when no particle has b -> a) chain
! each boundary corner c to its neighbours a (before) and b (after). The piece of corner c is
! the uniform quadratic B-spline of the control points (a, c, b),
!
!     x(u) = B0(u) x_a + B1(u) x_c + B2(u) x_b,   B0 = (1-u)^2/2, B1 = 1/2 + u - u^2, B2 = u^2/2,
!
! from the middle of a-c (u = 0) to the middle of c-b (u = 1): the pieces join with a common
! tangent (C1), and on a straight row of equally spaced corners the curve is that row.
!
! The control point of a smooth corner is not the corner itself but P_c = x_c - (x_a - 2 x_c +
! x_b) / 8: with the corners as control points the curve passes (x_a + 6 x_c + x_b) / 8, inside
! a convex surface by an eighth of the corners' second difference (on a ring of radius R with
! corners dtheta apart, R dtheta^2 / 8, as far as the chords' midpoints), so that a wall
! touching the corners would touch no curve and transmit nothing until it had moved that far
! (a wave pulse rising from zero speed, 1 m/s peak, would start 1.1 us late at h = t/8,
! n_thick = 8). With the shifted control points the curve passes through
! the corners to O(dtheta^4) (and through the midpoints of the arc between them), so that a
! wall touching the material surface at t = 0 pushes from the first step after it moves. A
! control point is a fixed combination of three corners, so a curve point is one of at most
! five (cid, phi) and the force stays the exact gradient of the energy. Sharp corners, chain
! ends and corners on a mirror plane whose piece is not the mirrored whole keep P_c = x_c; a
! corner whose piece is the mirrored whole takes the mirror image of its neighbour as its other
! neighbour. A sharp
! corner (the boundary turns by more than 45 degrees, e.g. the corner of a block, or where the
! ring's surface meets a cut face) is kept sharp: its piece is split at c into two straight
! halves, each the B-spline of c and one neighbour with the other replaced by its mirror
! 2 x_c - x_neighbour. At a chain end (a pinch, or no neighbour) only the half with a
! neighbour is kept.
!
! The contact energy of a piece with the plane (gap g(u) = (x(u) - x_w) . n, quadratic in u)
! is the penalty of its corner integrated over the piece,
!
!     E_c = w k_c int 1/2 min(g(u), 0)^2 du,      k_c = alpha m_c c^2 / h^2,
!
! w = 1 for a whole piece, 2 for a half (so that a flat face, uniformly pressed, is exactly as
! stiff as with corner contact). The force on the corners is -dE/dx: on corner m,
! -w k_c int_{g<0} g(u) phi_m(u) du n (phi_m the corner's coefficient in x(u)); the bounds of
! the region g < 0 contribute nothing since the integrand vanishes there. Both integrands are
! polynomials of degree 4 in u on the sub-intervals where g < 0 (bounded by the roots of g),
! so three Gauss-Legendre points per sub-interval integrate them exactly: each Gauss point is a
! surface point of mpm_surface_contact (force, energy, and the weights sum_m phi_m N_i(x_m) of
! the nodes of its corners, the velocity the code moves the curve point with), and the force
! is the exact gradient of the energy: the contact stays conservative, and its force and its
! point of action change continuously with the gap.
!
! A corner tied to a 'bonded' wall (mpm_surface_contact, surface_tie) has no piece: it is a
! point of its own (one corner, coefficient 1) with the spring to its anchor on the wall.
module mpm_surface_curve
  use mpm_kinds, only: wp
  use mpm_particles, only: particles_t
  use mpm_surface_contact, only: surface_work_t, surface_reserve, corner_masses, untied, &
                                 tie_force
  implicit none
  private
  public :: surface_curve_points

  real(wp), parameter :: sharp_cos = 0.70710678118654752_wp  !! cosine of the turn above which a
                                                             !! corner stays sharp (45 deg) [-]
  real(wp), parameter :: gauss_u(3) = [-0.77459666924148338_wp, 0.0_wp, &
                                       0.77459666924148338_wp]  !! Gauss-Legendre on [-1, 1]
  real(wp), parameter :: gauss_w(3) = [5.0_wp/9.0_wp, 8.0_wp/9.0_wp, 5.0_wp/9.0_wp]

contains

  !> The Gauss points of the surface curve (CPDI2 corners of p) that lie behind the plane
  !! through xw with unit normal `normal`, with their penalty forces and energies (stiffness
  !! kf m_c per corner), in wk (wk%npt of them, in corner order; wk%curve set).
  subroutine surface_curve_points(p, xw, normal, kf, mirror, tol, wk)
    type(particles_t), intent(in) :: p     !! particles (corners, masses)
    real(wp), intent(in) :: xw(2)          !! a point on the plane [m]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: kf             !! stiffness per unit point mass, alpha c^2/h^2 [1/s^2]
    real(wp), intent(in) :: mirror(:,:)    !! the mirror planes: point, unit normal (4, nm) [m, -]
    real(wp), intent(in) :: tol            !! distance under which a corner is on a plane [m]
    type(surface_work_t), intent(inout) :: wk  !! work arrays: the points
    integer :: ic, a, b, mc, q, k, la, lb
    real(wp) :: e1(2), e2(2), l1, l2
    logical :: sharp, ma, mb, clear
    wk%npt = 0
    wk%gmin = 0.0_wp
    wk%curve = .true.
    call corner_masses(p, wk)
    call boundary_chain(p, wk)
    if (.not. allocated(wk%dc)) allocate(wk%dc(p%nc), wk%dp(p%nc), wk%la(p%nc), wk%lb(p%nc))
    if (size(wk%dc) /= p%nc) then
      deallocate(wk%dc, wk%dp, wk%la, wk%lb)
      allocate(wk%dc(p%nc), wk%dp(p%nc), wk%la(p%nc), wk%lb(p%nc))
    end if
    ! only the boundary corners carry pieces, and only they are read below; the deepest
    ! corner of a mesh that is not folded (the basis stops a run that folds) is one of them
    do k = 1, size(wk%bnd)
      ic = wk%bnd(k)
      wk%dc(ic) = (p%xc(1, ic) - xw(1))*normal(1) + (p%xc(2, ic) - xw(2))*normal(2)
      wk%gmin = min(wk%gmin, wk%dc(ic))
    end do
    ! the control points' gaps (dp): a smooth corner's shifted by its second difference / 8
    do k = 1, size(wk%bnd)
      ic = wk%bnd(k)
      call smooth_pair(p, wk, normal, mirror, tol, ic, la, lb)
      wk%la(ic) = la
      wk%lb(ic) = lb
      wk%dp(ic) = wk%dc(ic)
      if (la > 0) wk%dp(ic) = wk%dc(ic) - 0.125_wp*(wk%dc(la) - 2.0_wp*wk%dc(ic) + wk%dc(lb))
    end do
    do k = 1, size(wk%bnd)
      ic = wk%bnd(k)
      a = wk%prv(ic)
      b = wk%nxt(ic)
      if (a <= 0 .and. b <= 0) cycle       ! pinched both ways, or a pinch and a chain end
      if (allocated(wk%x0)) then           ! a tied corner: a point of its own (below)
        if (wk%x0(1, ic) < untied) cycle
      end if
      ! every piece below needs a gap < 0 among c and its neighbours: none when all are >= 0
      ! (a NaN gap goes on, as before)
      if (wk%dp(ic) >= 0.0_wp) then
        clear = .true.
        if (a > 0) clear = wk%dp(a) >= 0.0_wp
        if (b > 0 .and. clear) clear = wk%dp(b) >= 0.0_wp
        if (clear) cycle
      end if
      ! a cut face on a mirror plane is no surface; where it ends at the surface, the piece
      ! of the corner is the whole one with the mirror image of its other neighbour (the
      ! full body's piece, whose image gap is the neighbour's when the wall is square to the
      ! mirror plane)
      mc = plane_of(p, mirror, tol, ic)
      ma = .false.
      mb = .false.
      if (mc > 0 .and. a > 0) ma = plane_of(p, mirror, tol, a) == mc
      if (mc > 0 .and. b > 0) mb = plane_of(p, mirror, tol, b) == mc
      if (ma .and. mb) cycle
      if (ma .or. mb) then
        q = merge(b, a, ma)
        if (q > 0 .and. abs(dot_product(normal, mirror(3:4, mc))) < 1.0e-9_wp) then
          if (min(wk%dp(q), wk%dp(ic)) < 0.0_wp) call piece(p, kf, ic, q, q, 0, 1.0_wp, wk)
          cycle
        end if
        if (ma) a = 0
        if (mb) b = 0
      end if
      if (a > 0 .and. b > 0) then          ! the piece lies in the hull of a, c, b
        if (min(wk%dp(a), wk%dp(ic), wk%dp(b)) >= 0.0_wp) cycle
        e1 = p%xc(:, ic) - p%xc(:, a)
        e2 = p%xc(:, b) - p%xc(:, ic)
        l1 = sqrt(e1(1)**2 + e1(2)**2)
        l2 = sqrt(e2(1)**2 + e2(2)**2)
        sharp = .not. (e1(1)*e2(1) + e1(2)*e2(2) > sharp_cos*l1*l2)
        if (.not. sharp) then
          call piece(p, kf, ic, a, b, 0, 1.0_wp, wk)
          cycle
        end if
      end if
      if (a > 0) then
        if (min(wk%dp(a), wk%dp(ic)) < 0.0_wp) call piece(p, kf, ic, a, b, 1, 2.0_wp, wk)
      end if
      if (b > 0) then
        if (min(wk%dp(ic), wk%dp(b)) < 0.0_wp) call piece(p, kf, ic, a, b, 2, 2.0_wp, wk)
      end if
    end do
    if (allocated(wk%x0)) call tied_corners(p, xw, normal, kf, wk)
  end subroutine surface_curve_points

  !> The corners tied to a 'bonded' wall, each a point of one corner with the spring k_c d
  !! to its anchor (mpm_surface_contact, tie_force), added to wk in corner order.
  subroutine tied_corners(p, xw, normal, kf, wk)
    type(particles_t), intent(in) :: p     !! particles (corners)
    real(wp), intent(in) :: xw(2)          !! a point on the plane [m]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: kf             !! stiffness per unit point mass [1/s^2]
    type(surface_work_t), intent(inout) :: wk  !! points added (x0, shift read)
    integer :: ic, j
    real(wp) :: d, fn, ft, en
    do ic = 1, p%nc
      if (.not. wk%x0(1, ic) < untied) cycle
      d = (p%xc(1, ic) - xw(1))*normal(1) + (p%xc(2, ic) - xw(2))*normal(2)
      wk%gmin = min(wk%gmin, d)
      call tie_force(p%xc(:, ic) - wk%x0(:, ic) - wk%shift, normal, kf*wk%corner_mass(ic), &
                     fn, ft, en)
      call new_point(wk, -ic, .true., j)
      wk%xq(:, :, j) = 0.0_wp
      wk%cid(1, j) = ic
      wk%phi(1, j) = 1.0_wp
      wk%xq(:, 1, j) = p%xc(:, ic)
      wk%xs(:, j) = p%xc(:, ic)
      wk%fn(j) = fn
      wk%ft(j) = ft
      wk%en(j) = en
    end do
  end subroutine tied_corners

  !> A new point at the end of wk (room reserved): its owner and tie, no corners yet.
  subroutine new_point(wk, owner, tied, j)
    type(surface_work_t), intent(inout) :: wk  !! points
    integer, intent(in) :: owner           !! the point's owner (-corner)
    logical, intent(in) :: tied            !! tied to a 'bonded' wall
    integer, intent(out) :: j              !! the new point
    call surface_reserve(wk, wk%npt + 1)
    wk%npt = wk%npt + 1
    j = wk%npt
    wk%owner(j) = owner
    wk%tied(j) = tied
    wk%cid(:, j) = 0
    wk%phi(:, j) = 0.0_wp
  end subroutine new_point

  !> The neighbours whose second difference shifts corner c's control point (la, lb; 0, 0
  !! when it keeps P_c = x_c): a smooth corner's two neighbours; for a corner on a mirror plane
  !! whose piece is the mirrored whole (the wall square to the plane), its neighbour off the
  !! plane twice (its mirror image has the same gap). The same cases as surface_curve_points.
  subroutine smooth_pair(p, wk, normal, mirror, tol, c, la, lb)
    type(particles_t), intent(in) :: p     !! particles (corners)
    type(surface_work_t), intent(in) :: wk !! boundary chain (nxt, prv)
    real(wp), intent(in) :: normal(2)      !! the wall's unit normal [-]
    real(wp), intent(in) :: mirror(:,:)    !! the mirror planes: point, unit normal (4, nm)
    real(wp), intent(in) :: tol            !! distance under which a corner is on a plane [m]
    integer, intent(in) :: c               !! corner
    integer, intent(out) :: la, lb         !! its neighbours for the shift, or 0
    integer :: a, b, mc
    logical :: ma, mb
    real(wp) :: e1(2), e2(2)
    la = 0
    lb = 0
    a = wk%prv(c)
    b = wk%nxt(c)
    if (a <= 0 .or. b <= 0) return
    mc = plane_of(p, mirror, tol, c)
    ma = .false.
    mb = .false.
    if (mc > 0) ma = plane_of(p, mirror, tol, a) == mc
    if (mc > 0) mb = plane_of(p, mirror, tol, b) == mc
    if (ma .and. mb) return
    if (ma .or. mb) then
      if (abs(dot_product(normal, mirror(3:4, mc))) >= 1.0e-9_wp) return
      la = merge(b, a, ma)
      lb = la
      return
    end if
    e1 = p%xc(:, c) - p%xc(:, a)
    e2 = p%xc(:, b) - p%xc(:, c)
    if (.not. (e1(1)*e2(1) + e1(2)*e2(2) > sharp_cos*sqrt(e1(1)**2 + e1(2)**2)* &
                                            sqrt(e2(1)**2 + e2(2)**2))) return
    la = a
    lb = b
  end subroutine smooth_pair

  !> The first mirror plane corner c lies on, or 0.
  pure integer function plane_of(p, mirror, tol, c)
    type(particles_t), intent(in) :: p   !! particles (corners)
    real(wp), intent(in) :: mirror(:,:)  !! mirror planes: point, unit normal (4, nm)
    real(wp), intent(in) :: tol          !! distance under which a corner is on a plane [m]
    integer, intent(in) :: c             !! corner
    integer :: m
    plane_of = 0
    do m = 1, size(mirror, 2)
      if (abs(dot_product(p%xc(:, c) - mirror(1:2, m), mirror(3:4, m))) > tol) cycle
      plane_of = m
      return
    end do
  end function plane_of

  !> The Gauss points of corner c's piece (kind 0: whole, 1: the half towards a, 2: towards
  !! b) where its gap wk%dc is negative, added to wk; w the weight of the piece.
  subroutine piece(p, kf, c, a, b, kind, w, wk)
    type(particles_t), intent(in) :: p   !! particles (corners)
    real(wp), intent(in) :: kf           !! stiffness per unit point mass [1/s^2]
    integer, intent(in) :: c, a, b       !! the corner and its neighbours
    integer, intent(in) :: kind          !! 0 whole, 1 half towards a, 2 half towards b
    real(wp), intent(in) :: w            !! weight of the piece [-]
    type(surface_work_t), intent(inout) :: wk  !! points added
    real(wp) :: gc(3), qa, qb, qc, u0, u1, br(4), rt(2), disc, q, um, lo, len, u, bs(3), g, phi(3), k
    integer :: ids(3), nb, i, j, iq, m
    ! control gaps: the control points', or a mirrored neighbour's 2 g_c - g_n
    select case (kind)
    case (0)
      ids = [a, c, b]
      gc = [wk%dp(a), wk%dp(c), wk%dp(b)]
      u0 = 0.0_wp; u1 = 1.0_wp
    case (1)
      ids = [a, c, 0]
      gc = [wk%dp(a), wk%dp(c), 2.0_wp*wk%dp(c) - wk%dp(a)]
      u0 = 0.0_wp; u1 = 0.5_wp
    case default
      ids = [0, c, b]
      gc = [2.0_wp*wk%dp(c) - wk%dp(b), wk%dp(c), wk%dp(b)]
      u0 = 0.5_wp; u1 = 1.0_wp
    end select
    ! g(u) = qa u^2 + qb u + qc; break points: the ends and the roots inside
    qa = 0.5_wp*(gc(1) - 2.0_wp*gc(2) + gc(3))
    qb = gc(2) - gc(1)
    qc = 0.5_wp*(gc(1) + gc(2))
    nb = 1
    br(1) = u0
    rt = -1.0_wp
    if (qa /= 0.0_wp) then
      disc = qb*qb - 4.0_wp*qa*qc
      if (disc > 0.0_wp) then
        q = -0.5_wp*(qb + sign(sqrt(disc), qb))
        if (q /= 0.0_wp) then
          rt = [q/qa, qc/q]
        end if
      end if
    else if (qb /= 0.0_wp) then
      rt(1) = -qc/qb
    end if
    do i = 1, 2
      if (rt(i) > u0 .and. rt(i) < u1) then
        nb = nb + 1
        br(nb) = rt(i)
      end if
    end do
    nb = nb + 1
    br(nb) = u1
    if (nb == 4) then                    ! two roots inside: in order
      if (br(2) > br(3)) br(2:3) = [br(3), br(2)]
    end if
    k = w*kf*wk%corner_mass(c)
    do i = 1, nb - 1
      lo = br(i)
      len = br(i + 1) - lo
      if (.not. len > 0.0_wp) cycle
      um = lo + 0.5_wp*len
      if (.not. (qa*um + qb)*um + qc < 0.0_wp) cycle
      do iq = 1, 3
        u = um + 0.5_wp*len*gauss_u(iq)
        bs = [0.5_wp*(1.0_wp - u)**2, 0.5_wp + u - u*u, 0.5_wp*u*u]
        g = (qa*u + qb)*u + qc
        if (.not. g < 0.0_wp) cycle
        select case (kind)                 ! coefficients of the real corners
        case (0)
          phi = bs
        case (1)
          phi = [bs(1) - bs(3), bs(2) + 2.0_wp*bs(3), 0.0_wp]
        case default
          phi = [0.0_wp, 2.0_wp*bs(1) + bs(2), bs(3) - bs(1)]
        end select
        call new_point(wk, -c, .false., j)
        do m = 1, 3                        ! the control points' corners (P_c, smooth_pair)
          if (ids(m) == 0) cycle
          if (wk%la(ids(m)) > 0) then
            call add(j, ids(m), 1.25_wp*phi(m))
            call add(j, wk%la(ids(m)), -0.125_wp*phi(m))
            call add(j, wk%lb(ids(m)), -0.125_wp*phi(m))
          else
            call add(j, ids(m), phi(m))
          end if
        end do
        wk%xs(:, j) = 0.0_wp
        do m = 1, size(wk%cid, 1)
          wk%xq(:, m, j) = 0.0_wp
          if (wk%cid(m, j) == 0) cycle
          wk%xq(:, m, j) = p%xc(:, wk%cid(m, j))
          wk%xs(:, j) = wk%xs(:, j) + wk%phi(m, j)*p%xc(:, wk%cid(m, j))
        end do
        wk%fn(j) = -k*0.5_wp*len*gauss_w(iq)*g
        wk%en(j) = 0.5_wp*k*0.5_wp*len*gauss_w(iq)*g*g
      end do
    end do
  contains
    !> Coefficient f of corner id on point j, merged with an earlier entry of the same corner.
    subroutine add(j, id, f)
      integer, intent(in) :: j, id
      real(wp), intent(in) :: f
      integer :: r
      do r = 1, size(wk%cid, 1)
        if (wk%cid(r, j) == id .or. wk%cid(r, j) == 0) then
          wk%cid(r, j) = id
          wk%phi(r, j) = wk%phi(r, j) + f
          return
        end if
      end do
    end subroutine add
  end subroutine piece


  !> The boundary chain of the CPDI2 corners (computed once: the corners' connectivity does
  !! not change): nxt(c), prv(c) the neighbours along the boundary, 0 for an inner corner, -1
  !! where the boundary pinches (a corner with two boundary edges out or in); bnd the
  !! boundary corners in increasing order.
  subroutine boundary_chain(p, wk)
    type(particles_t), intent(in) :: p     !! particles (corner ids)
    type(surface_work_t), intent(inout) :: wk  !! nxt, prv, bnd set
    integer, allocatable :: out(:,:), nout(:)
    integer :: ip, a, ca, cb
    if (allocated(wk%nxt)) then
      if (size(wk%nxt) == p%nc) return
      deallocate(wk%nxt, wk%prv, wk%bnd)
    end if
    allocate(wk%nxt(p%nc), wk%prv(p%nc), out(4, p%nc), nout(p%nc))
    wk%nxt = 0
    wk%prv = 0
    nout = 0
    do ip = 1, p%np
      do a = 1, 4
        ca = p%corner(a, ip)
        if (nout(ca) == 4) cycle             ! not a valid mesh corner; leave it inside
        nout(ca) = nout(ca) + 1
        out(nout(ca), ca) = p%corner(mod(a, 4) + 1, ip)
      end do
    end do
    do ip = 1, p%np
      do a = 1, 4
        ca = p%corner(a, ip)
        cb = p%corner(mod(a, 4) + 1, ip)
        if (any(out(1:nout(cb), cb) == ca)) cycle   ! shared with the neighbour: inside
        if (wk%nxt(ca) == 0) then
          wk%nxt(ca) = cb
        else
          wk%nxt(ca) = -1
        end if
        if (wk%prv(cb) == 0) then
          wk%prv(cb) = ca
        else
          wk%prv(cb) = -1
        end if
      end do
    end do
    wk%bnd = pack([(ca, ca = 1, p%nc)], wk%prv /= 0 .or. wk%nxt /= 0)
  end subroutine boundary_chain

end module mpm_surface_curve
