!> The filler of a tube (`&body shape = 'filler'`, a foam core): the particles that fill the
!! tube's inner face, less a gap, as a radial O-grid (docs/method.md, "Sections").
! SPDX-License-Identifier: MIT
module mpm_filler
  use mpm_kinds, only: wp
  use mpm_sections, only: section_t, section_tube, push_quad, quad_area
  use mpm_point_merge, only: merge_points
  use mpm_strings, only: sci
  implicit none
  private
  public :: filler_mesh

contains

  !> A filler of a tube (a foam core): the particles of the tube's inner face (tube_inner_face)
  !! moved inwards by `gap`, a convex polygon, as a radial O-grid about a centre o (the
  !! polygon's centroid; on the mirror planes x = c(1), and y = c(2) for a quarter):
  !! - a central rectangle, its sides at 0.6 of the polygon's extent from o along x and y,
  !!   divided nx x ny by straight lines between the nodes of opposite sides (nx, ny even, the
  !!   larger n, the smaller in proportion to the extents);
  !! - four blocks between its sides and the polygon, each node of a side joined to the point
  !!   where the ray from o through it meets the polygon, m divisions out (m: the blocks' mean
  !!   depth over the rectangle's mean spacing).
  !! A side's nodes are its uniform ones (n/2 on each side of o's line, so that the lines
  !! x = o(1) and y = o(2) are mesh lines) and the points where the rays from o through the
  !! polygon's vertices cross it, whose block lines end at the vertices themselves; uniform
  !! nodes within half a spacing of a vertex's are dropped (but the ends and o's line), and
  !! opposite half-sides are evened by halving their widest gaps. The polygon's vertices are
  !! thus among the boundary nodes and the particles tile it exactly; every block line is a
  !! ray from o, so a block's particles are convex trapezoids, and the rectangle's lines do
  !! not cross. A rounded corner's chords each start a ray: thin particles run from the corner
  !! to the rectangle, and along its sides. `parts` keeps the particles of x >= c(1) (2) and
  !! y >= c(2) (4), as disc_mesh. stat /= 0 with msg: the inner face not convex, the gap
  !! closing an edge of it (the largest gap allowed in msg), o not inside.
  pure subroutine filler_mesh(vert, t, rc, dl, gap, center, parts, n_div, xc, quad, stat, msg)
    real(wp), intent(in) :: vert(:,:)      !! the tube's centreline vertices (2, nv) [m]
    real(wp), intent(in) :: t, rc, dl      !! its thickness, corner radius, chord length [m]
    real(wp), intent(in) :: gap            !! gap to the inner face [m]
    real(wp), intent(in) :: center(2)      !! the mirror planes' point [m]
    integer, intent(in) :: parts           !! 1 the whole filler, 2 the half, 4 the quarter
    integer, intent(in) :: n_div           !! divisions of the rectangle's longer side
    real(wp), allocatable, intent(out) :: xc(:,:)  !! corners (2, nc) [m]
    integer, allocatable, intent(out) :: quad(:,:) !! corners of each particle (4, np)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    real(wp), parameter :: lam = 0.6_wp    ! the rectangle's share of the extents [-]
    real(wp), allocatable :: poly(:,:), q(:,:,:), pts(:,:)
    real(wp), allocatable :: crd(:,:)      ! per side: node coordinates along it (x or y)
    real(wp), allocatable :: fix(:,:,:)    ! per side and node: its vertex, or huge
    integer, allocatable :: qw(:), ids(:)
    integer :: nsd(4), nq, i, nx, ny, keep
    real(wp) :: o(2), lo(2), hi(2), size_, ext(2), c(2)
    allocate(xc(2, 0), quad(4, 0))
    call filler_polygon(vert, t, rc, dl, gap, center, parts, poly, o, size_, stat, msg)
    if (stat /= 0) return
    lo = o - lam*(o - minval(poly, dim=2))
    hi = o + lam*(maxval(poly, dim=2) - o)
    ext = hi - lo
    nx = max(2, 2*((n_div + 1)/2))
    ny = nx
    if (ext(1) > ext(2)) ny = max(2, 2*nint(0.5_wp*real(nx, wp)*ext(2)/ext(1)))
    if (ext(2) > ext(1)) nx = max(2, 2*nint(0.5_wp*real(ny, wp)*ext(1)/ext(2)))
    call side_nodes(poly, o, lo, hi, nx, ny, crd, fix, nsd)
    allocate(q(2, 4, 64), qw(64))
    nq = 0
    call core_quads(crd, nsd, lo, hi, q, qw, nq)
    call block_quads(poly, o, crd, fix, nsd, lo, hi, q, qw, nq)
    keep = 0                               ! the sector's particles (centroids off the lines)
    do i = 1, nq
      c = 0.25_wp*sum(q(:, :, i), dim=2) - o
      if ((parts >= 2 .and. c(1) < 0.0_wp) .or. (parts >= 4 .and. c(2) < 0.0_wp)) cycle
      keep = keep + 1
      q(:, :, keep) = q(:, :, i)
    end do
    nq = keep
    do i = 1, nq
      if (.not. quad_area(q(:, :, i)) > 0.0_wp) then
        stat = 1
        msg = 'a particle of the filler turns inside out (internal: report it)'
        return
      end if
    end do
    pts = reshape(q(:, :, 1:nq), [2, 4*nq])
    call merge_points(pts, 1.0e-9_wp*size_, xc, ids)
    quad = reshape(ids, [4, nq])
  end subroutine filler_mesh

  !> The filler's polygon: the tube's centreline moved in by t/2 + gap (convex_offset), the
  !! inner face of its particles (where the faces of its walls' strips meet, mitred:
  !! mpm_sections) less the gap, and the centre o of its mesh (the centroid; on the mirror
  !! planes of a half or quarter), strictly inside it; size_, the centreline's extent [m].
  pure subroutine filler_polygon(vert, t, rc, dl, gap, center, parts, poly, o, size_, stat, msg)
    real(wp), intent(in) :: vert(:,:)      !! the tube's centreline vertices (2, nv) [m]
    real(wp), intent(in) :: t, rc, dl      !! its thickness, corner radius, chord length [m]
    real(wp), intent(in) :: gap            !! gap to the inner face [m]
    real(wp), intent(in) :: center(2)      !! the mirror planes' point [m]
    integer, intent(in) :: parts           !! 1 the whole filler, 2 the half, 4 the quarter
    real(wp), allocatable, intent(out) :: poly(:,:)  !! the polygon (2, nv) [m]
    real(wp), intent(out) :: o(2)          !! the mesh's centre [m]
    real(wp), intent(out) :: size_         !! the polygon's largest extent [m]
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    type(section_t) :: s
    integer :: k, nv
    real(wp) :: a
    o = 0.0_wp
    size_ = 0.0_wp
    call section_tube(vert, t, rc, dl, s)  ! its centreline (the chords' nodes, in order)
    poly = s%xn
    size_ = maxval(maxval(poly, dim=2) - minval(poly, dim=2))
    call convex_offset(poly, 0.5_wp*t + gap, 0.5_wp*t, size_, stat, msg)
    if (stat /= 0) return
    nv = size(poly, 2)
    o = polygon_centroid(poly)
    if (parts >= 2) o(1) = center(1)
    if (parts >= 4) o(2) = center(2)
    do k = 1, nv                           ! o strictly inside
      a = cross2(poly(:, 1 + mod(k, nv)) - poly(:, k), o - poly(:, k))
      if (.not. a > 1.0e-9_wp*size_*norm2(poly(:, 1 + mod(k, nv)) - poly(:, k))) then
        stat = 1
        msg = 'the centre ('//sci(o(1), 3)//', '//sci(o(2), 3)//') m of its '// &
          'mesh is not inside the inner face (a half or quarter filler is centred on the '// &
          'tube''s mirror planes)'
        return
      end if
    end do
  end subroutine filler_polygon

  !> The central rectangle's particles: column i from the bottom's node i to the top's, row j
  !! from the left's to the right's; node (i, j) where they cross (x from the column, y from
  !! the row: exact on o's lines).
  pure subroutine core_quads(crd, nsd, lo, hi, q, qw, nq)
    real(wp), intent(in) :: crd(:,:)       !! the sides' node coordinates
    integer, intent(in) :: nsd(4)          !! nodes of each side
    real(wp), intent(in) :: lo(2), hi(2)   !! the rectangle's corners [m]
    real(wp), allocatable, intent(inout) :: q(:,:,:)
    integer, allocatable, intent(inout) :: qw(:)
    integer, intent(inout) :: nq
    real(wp), allocatable :: g(:,:,:)
    real(wp) :: xi, eta, bx, tx, ly, ry, ext(2)
    integer :: i, j
    ext = hi - lo
    allocate(g(2, 0:nsd(1) - 1, 0:nsd(2) - 1))
    do j = 0, nsd(2) - 1
      do i = 0, nsd(1) - 1
        bx = crd(i + 1, 1)
        tx = crd(i + 1, 3)
        ly = crd(j + 1, 4)
        ry = crd(j + 1, 2)
        xi = ((bx - lo(1))/ext(1) + (tx - bx)/ext(1)*(ly - lo(2))/ext(2))/ &
             (1.0_wp - (tx - bx)/ext(1)*(ry - ly)/ext(2))
        eta = (ly - lo(2))/ext(2) + (ry - ly)/ext(2)*xi
        g(:, i, j) = [bx + (tx - bx)*eta, ly + (ry - ly)*xi]
        if (j == 0) g(:, i, j) = [bx, lo(2)]
        if (j == nsd(2) - 1) g(:, i, j) = [tx, hi(2)]
        if (i == 0) g(:, i, j) = [lo(1), ly]
        if (i == nsd(1) - 1) g(:, i, j) = [hi(1), ry]
      end do
    end do
    do j = 0, nsd(2) - 2
      do i = 0, nsd(1) - 2
        call push_quad(q, qw, nq, reshape([g(:, i, j), g(:, i + 1, j), g(:, i + 1, j + 1), &
                       g(:, i, j + 1)], [2, 4]), 0)
      end do
    end do
  end subroutine core_quads

  !> The four blocks' particles: each node of a side joined to its point on the polygon (the
  !! vertex where the node is a vertex's, else where the ray from o through it leaves the
  !! polygon), m divisions out (their mean depth over the rectangle's mean spacing).
  pure subroutine block_quads(poly, o, crd, fix, nsd, lo, hi, q, qw, nq)
    real(wp), intent(in) :: poly(:,:), o(2)
    real(wp), intent(in) :: crd(:,:), fix(:,:,:)
    integer, intent(in) :: nsd(4)
    real(wp), intent(in) :: lo(2), hi(2)
    real(wp), allocatable, intent(inout) :: q(:,:,:)
    integer, allocatable, intent(inout) :: qw(:)
    integer, intent(inout) :: nq
    real(wp), allocatable :: pin(:,:), pbd(:,:)
    real(wp) :: depth, spacing, p(2, 4)
    integer :: sd, i, j, m
    depth = 0.0_wp
    spacing = (2.0_wp*(hi(1) - lo(1)) + 2.0_wp*(hi(2) - lo(2)))/real(sum(nsd) - 4, wp)
    do sd = 1, 4
      call block_points(sd, pin, pbd)
      depth = depth + sum(norm2(pbd - pin, dim=1))
    end do
    m = max(1, nint(depth/real(sum(nsd), wp)/spacing))
    do sd = 1, 4
      call block_points(sd, pin, pbd)
      do j = 0, m - 1
        do i = 1, nsd(sd) - 1
          p(:, 1) = out_point(i, j)
          p(:, 2) = out_point(i + 1, j)
          p(:, 3) = out_point(i + 1, j + 1)
          p(:, 4) = out_point(i, j + 1)
          if (quad_area(p) < 0.0_wp) p = p(:, [4, 3, 2, 1])
          call push_quad(q, qw, nq, p, 0)
        end do
      end do
    end do
  contains
    !> Side sd's nodes on the rectangle (pin) and on the polygon (pbd).
    pure subroutine block_points(sd, pin, pbd)
      integer, intent(in) :: sd
      real(wp), allocatable, intent(out) :: pin(:,:), pbd(:,:)
      integer :: i
      allocate(pin(2, nsd(sd)), pbd(2, nsd(sd)))
      do i = 1, nsd(sd)
        select case (sd)
        case (1)
          pin(:, i) = [crd(i, sd), lo(2)]
        case (2)
          pin(:, i) = [hi(1), crd(i, sd)]
        case (3)
          pin(:, i) = [crd(i, sd), hi(2)]
        case default
          pin(:, i) = [lo(1), crd(i, sd)]
        end select
        if (fix(1, i, sd) < huge(1.0_wp)) then
          pbd(:, i) = fix(:, i, sd)
        else
          pbd(:, i) = ray_exit(poly, o, pin(:, i) - o)
        end if
      end do
    end subroutine block_points
    !> The point j of m out along block line i (1-based) of the current side.
    pure function out_point(i, j) result(x)
      integer, intent(in) :: i, j
      real(wp) :: x(2)
      if (j == 0) then
        x = pin(:, i)
      else if (j == m) then
        x = pbd(:, i)
      else
        x = pin(:, i) + (real(j, wp)/real(m, wp))*(pbd(:, i) - pin(:, i))
      end if
    end function out_point
  end subroutine block_quads

  !> The nodes of the four sides of the rectangle lo-hi (1 bottom, 2 right, 3 top, 4 left; along
  !! x for 1 and 3, along y for 2 and 4, increasing): crd(1:nsd(sd), sd) their coordinates,
  !! fix(:, i, sd) the vertex whose ray from o crosses the side there (huge: none).
  pure subroutine side_nodes(poly, o, lo, hi, nx, ny, crd, fix, nsd)
    real(wp), intent(in) :: poly(:,:), o(2), lo(2), hi(2)
    integer, intent(in) :: nx, ny          !! uniform divisions along x and y (even)
    real(wp), allocatable, intent(out) :: crd(:,:), fix(:,:,:)
    integer, intent(out) :: nsd(4)
    real(wp), allocatable :: vc(:), vx(:,:), uc(:)
    integer :: sd, k, ax, nd, nmax, i, nvs
    real(wp) :: d(2), tx, ty, tau, x, delta(2), cmid, tol, span(2)
    logical :: near
    nmax = 2*(max(nx, ny) + 1 + size(poly, 2))
    allocate(crd(nmax, 4), fix(2, nmax, 4))
    fix = huge(1.0_wp)
    do sd = 1, 4
      ax = merge(1, 2, sd == 1 .or. sd == 3)     ! the coordinate along the side
      nd = merge(nx, ny, ax == 1)
      span = [lo(ax), hi(ax)]
      cmid = o(ax)
      delta = [(cmid - span(1))/real(nd/2, wp), (span(2) - cmid)/real(nd/2, wp)]
      tol = 1.0e-9_wp*(span(2) - span(1))
      ! the vertices whose ray crosses this side (the rectangle's corners: both sides)
      allocate(vc(0), vx(2, 0))
      do k = 1, size(poly, 2)
        d = poly(:, k) - o
        tx = huge(1.0_wp)
        ty = huge(1.0_wp)
        if (d(1) > 0.0_wp) tx = (hi(1) - o(1))/d(1)
        if (d(1) < 0.0_wp) tx = (lo(1) - o(1))/d(1)
        if (d(2) > 0.0_wp) ty = (hi(2) - o(2))/d(2)
        if (d(2) < 0.0_wp) ty = (lo(2) - o(2))/d(2)
        tau = min(tx, ty)
        select case (sd)                   ! does the ray leave through side sd?
        case (1)
          if (.not. (d(2) < 0.0_wp .and. ty <= tx*(1.0_wp + 1.0e-12_wp))) cycle
        case (2)
          if (.not. (d(1) > 0.0_wp .and. tx <= ty*(1.0_wp + 1.0e-12_wp))) cycle
        case (3)
          if (.not. (d(2) > 0.0_wp .and. ty <= tx*(1.0_wp + 1.0e-12_wp))) cycle
        case default
          if (.not. (d(1) < 0.0_wp .and. tx <= ty*(1.0_wp + 1.0e-12_wp))) cycle
        end select
        x = o(ax) + tau*d(ax)
        if (abs(x - o(ax)) <= tol) x = o(ax)           ! on o's line
        x = max(span(1), min(span(2), x))
        if (abs(x - span(1)) <= tol) x = span(1)       ! at a corner
        if (abs(x - span(2)) <= tol) x = span(2)
        vc = [vc, x]
        vx = reshape([vx, poly(:, k)], [2, size(vc)])
      end do
      nvs = size(vc)
      ! the uniform nodes, less those within half a spacing of a vertex's (but the ends and
      ! o's line, which a vertex there replaces)
      allocate(uc(0))
      do i = 0, nd
        if (i <= nd/2) then
          x = span(1) + delta(1)*real(i, wp)
        else
          x = cmid + delta(2)*real(i - nd/2, wp)
        end if
        if (i == nd/2) x = cmid
        if (i == nd) x = span(2)
        near = .false.
        do k = 1, nvs
          if (i == 0 .or. i == nd/2 .or. i == nd) then
            near = near .or. vc(k) == x
          else
            near = near .or. abs(vc(k) - x) < 0.5_wp*delta(merge(1, 2, i < nd/2))
          end if
        end do
        if (.not. near) uc = [uc, x]
      end do
      nsd(sd) = size(uc) + nvs
      crd(1:size(uc), sd) = uc
      crd(size(uc) + 1:nsd(sd), sd) = vc
      fix(:, size(uc) + 1:nsd(sd), sd) = vx
      call sort_nodes(crd(1:nsd(sd), sd), fix(:, 1:nsd(sd), sd))
      deallocate(vc, vx, uc)
    end do
    ! opposite half-sides (split at o's line) get as many nodes: the bottom's and the top's
    ! columns, the left's and the right's rows
    call even_sides(crd(:, 1), fix(:, :, 1), nsd(1), crd(:, 3), fix(:, :, 3), nsd(3), o(1))
    call even_sides(crd(:, 4), fix(:, :, 4), nsd(4), crd(:, 2), fix(:, :, 2), nsd(2), o(2))
  end subroutine side_nodes

  !> Two opposite sides' nodes (coordinates c, vertices f, counts n) evened out on each side of
  !! cmid: a node in the middle of the widest gap of the half with fewer, until they match.
  pure subroutine even_sides(ca, fa, na, cb, fb, nb, cmid)
    real(wp), intent(inout) :: ca(:), fa(:,:), cb(:), fb(:,:)
    integer, intent(inout) :: na, nb
    real(wp), intent(in) :: cmid           !! o's coordinate along the sides [m]
    integer :: half, ka, kb
    do half = 1, 2
      do
        if (half == 1) then
          ka = count(ca(1:na) < cmid)
          kb = count(cb(1:nb) < cmid)
        else
          ka = count(ca(1:na) > cmid)
          kb = count(cb(1:nb) > cmid)
        end if
        if (ka == kb) exit
        if (ka < kb) then
          call split_widest(ca, fa, na, half, cmid)
        else
          call split_widest(cb, fb, nb, half, cmid)
        end if
      end do
    end do
  end subroutine even_sides

  !> A node in the middle of the widest gap of one half (1: below cmid, 2: above) of a side.
  pure subroutine split_widest(c, f, n, half, cmid)
    real(wp), intent(inout) :: c(:), f(:,:)
    integer, intent(inout) :: n
    integer, intent(in) :: half
    real(wp), intent(in) :: cmid
    integer :: i, iw
    real(wp) :: w, wmax
    iw = 0
    wmax = -1.0_wp
    do i = 1, n - 1
      if (half == 1 .and. c(i + 1) > cmid) cycle
      if (half == 2 .and. c(i) < cmid) cycle
      w = c(i + 1) - c(i)
      if (w > wmax) then
        wmax = w
        iw = i
      end if
    end do
    c(iw + 2:n + 1) = c(iw + 1:n)
    f(:, iw + 2:n + 1) = f(:, iw + 1:n)
    c(iw + 1) = 0.5_wp*(c(iw) + c(iw + 2))
    f(:, iw + 1) = huge(1.0_wp)
    n = n + 1
  end subroutine split_widest

  !> Sort side nodes by coordinate (insertion sort: a few hundred at most), their vertices along.
  pure subroutine sort_nodes(c, f)
    real(wp), intent(inout) :: c(:), f(:,:)
    integer :: i, k
    real(wp) :: tc, tf(2)
    do i = 2, size(c)
      tc = c(i)
      tf = f(:, i)
      k = i - 1
      do while (k >= 1)
        if (c(k) <= tc) exit
        c(k + 1) = c(k)
        f(:, k + 1) = f(:, k)
        k = k - 1
      end do
      c(k + 1) = tc
      f(:, k + 1) = tf
    end do
  end subroutine sort_nodes

  !> Where the ray from o (inside the convex counter-clockwise polygon) along d leaves it: on
  !! the edge it crosses, p + s (q - p) with s in [0, 1] [m].
  pure function ray_exit(poly, o, d) result(x)
    real(wp), intent(in) :: poly(:,:), o(2), d(2)
    real(wp) :: x(2)
    integer :: k, nv
    real(wp) :: e(2), den, sg, best, tau
    nv = size(poly, 2)
    x = o
    best = huge(1.0_wp)
    do k = 1, nv
      e = poly(:, 1 + mod(k, nv)) - poly(:, k)
      den = cross2(d, e)
      if (.not. den > 0.0_wp) cycle        ! the ray leaves through edges it sees from inside
      tau = cross2(poly(:, k) - o, e)/den
      sg = cross2(poly(:, k) - o, d)/den
      if (sg < -1.0e-12_wp .or. sg > 1.0_wp + 1.0e-12_wp .or. tau < 0.0_wp) cycle
      if (tau < best) then
        best = tau
        x = poly(:, k) + max(0.0_wp, min(1.0_wp, sg))*e
      end if
    end do
  end function ray_exit

  !> A convex counter-clockwise polygon moved inwards by gap >= 0 (each edge along its inward
  !! normal; a vertex where the moved edges meet); stat /= 0 when the polygon is not convex
  !! or the gap closes an edge (msg gives the largest gap: an edge of length L between turns
  !! phi_a, phi_b shortens by gap (tan(phi_a/2) + tan(phi_b/2))).
  pure subroutine convex_offset(poly, gap, half_t, size_, stat, msg)
    real(wp), allocatable, intent(inout) :: poly(:,:)  !! vertices (2, nv) [m]
    real(wp), intent(in) :: gap            !! inward distance [m]
    real(wp), intent(in) :: half_t         !! the part of it that is not fill_gap [m]
    real(wp), intent(in) :: size_          !! the polygon's size (tolerances) [m]
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    real(wp), allocatable :: turn(:), out(:,:)
    real(wp) :: u1(2), u2(2), n1(2), n2(2), gmax, shrink, len_k
    integer :: k, nv, kp, kn
    stat = 0
    msg = ''
    nv = size(poly, 2)
    allocate(turn(nv), out(2, nv))
    do k = 1, nv
      kp = 1 + modulo(k - 2, nv)
      kn = 1 + mod(k, nv)
      u1 = (poly(:, k) - poly(:, kp))/norm2(poly(:, k) - poly(:, kp))
      u2 = (poly(:, kn) - poly(:, k))/norm2(poly(:, kn) - poly(:, k))
      turn(k) = atan2(cross2(u1, u2), dot_product(u1, u2))
      if (cross2(u1, u2) < -1.0e-12_wp) then
        stat = 1
        msg = 'the tube turns inwards at ('//sci(poly(1, k), 3)//', '// &
          sci(poly(2, k), 3)//') m (its centreline): a filler needs a convex inner face'
        return
      end if
      n1 = [-u1(2), u1(1)]
      n2 = [-u2(2), u2(1)]
      out(:, k) = poly(:, k) + gap*(n1 + n2)/(1.0_wp + dot_product(n1, n2))
    end do
    if (.not. gap > 0.0_wp) return
    gmax = huge(1.0_wp)
    do k = 1, nv
      kn = 1 + mod(k, nv)
      len_k = norm2(poly(:, kn) - poly(:, k))
      shrink = tan(0.5_wp*max(turn(k), 0.0_wp)) + tan(0.5_wp*max(turn(kn), 0.0_wp))
      if (shrink > 0.0_wp) gmax = min(gmax, len_k/shrink)
    end do
    if (.not. gap < gmax - 1.0e-9_wp*size_) then
      stat = 1
      msg = 'the gap closes an edge of the tube''s inner face (fill_gap must be below '// &
        sci(gmax - half_t, 3)//' m)'
      return
    end if
    poly = out
  end subroutine convex_offset

  !> The centroid of a polygon (shoelace) [m].
  pure function polygon_centroid(poly) result(c)
    real(wp), intent(in) :: poly(:,:)
    real(wp) :: c(2), a, w
    integer :: k, kn, nv
    nv = size(poly, 2)
    a = 0.0_wp
    c = 0.0_wp
    do k = 1, nv
      kn = 1 + mod(k, nv)
      w = poly(1, k)*poly(2, kn) - poly(1, kn)*poly(2, k)
      a = a + w
      c = c + w*(poly(:, k) + poly(:, kn))
    end do
    c = c/(3.0_wp*a)
  end function polygon_centroid

  !> The z component of a x b.
  pure real(wp) function cross2(a, b)
    real(wp), intent(in) :: a(2), b(2)
    cross2 = a(1)*b(2) - a(2)*b(1)
  end function cross2
end module mpm_filler
