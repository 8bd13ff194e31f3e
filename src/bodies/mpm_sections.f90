!> Thin-walled sections beyond the ring: a wall graph (straight walls of given thickness joined
!! where their ends meet) and the conforming quadrilateral particles that fill it.
! SPDX-License-Identifier: MIT
!
! A section is a graph: nodes (points of the walls' centrelines) and edges (straight walls of
! thickness t between two nodes). A 'tube' is one closed polygon (its corners rounded on the
! centreline by chords of an arc), a 'honeycomb' the walls of a panel of hexagonal or
! re-entrant cells, 'walls' any graph read from a file. docs/method.md, "Sections".
!
! The particles (section_mesh). Each wall is a strip between its two faces, the lines at +-t/2
! from its centreline, cut at each end by a straight line; the strip is n_thick particles
! through and about square ones along (the bilinear division of the strip's quadrilateral,
! whose lines are straight, so the particles tile it exactly). Where walls meet, the cuts are
! where the faces meet:
! - two walls (a corner): the faces of the two walls meet on each side (a mitre), so the two
!   strips share their cut and nothing is left between them;
! - three or more (a Y or a T): the faces of consecutive walls around the joint (counter-
!   clockwise) meet at a point, (t/2) / tan(gap/2) out from the node (behind it where the gap
!   between them is over 180 degrees); where two walls are in line (the through wall of a T)
!   each face ends across from its other face's end. The points, in order, are the corners of
!   a core polygon: a quadrilateral is divided into n x n particles, another polygon into one
!   quadrilateral per corner (its corner, the midpoints of its two sides and the centroid),
!   each divided n/2 x n/2 (n = n_thick, even);
! - a free end: the cut is square to the wall at its node.
! Neighbouring particles share their corners (merged by position), as CPDI2 and the surface
! curve need. The summed area is the section's exactly: the strips and cores tile the union
! of the walls, mitred at corners.
! The colours of the walls for self-contact are mpm_section_colours.
module mpm_sections
  use mpm_kinds, only: wp
  use mpm_constants, only: pi
  use mpm_point_merge, only: merge_points
  use mpm_strings, only: itoa, sci
  implicit none
  private
  public :: section_t, section_tube, section_honeycomb, section_walls, section_mesh, push_quad, &
            quad_area, &
            section_area, section_length, disc_mesh, section_clip, incident, max_deg, merge_points

  integer, parameter :: max_deg = 16       !! walls at one joint, at most

  !> A wall graph.
  type :: section_t
    integer :: nn = 0                      !! nodes
    integer :: ne = 0                      !! walls (edges)
    real(wp), allocatable :: xn(:,:)       !! node positions (2, nn) [m]
    integer, allocatable :: en(:,:)        !! the two nodes of each wall (2, ne)
    real(wp), allocatable :: et(:)         !! wall thickness (ne) [m]
    integer, allocatable :: ew(:)          !! the logical wall of each edge (a tube's side with
                                           !! the halves of its rounded corners) (ne)
  end type section_t

contains

  ! ------------------------------------------------------------------ graphs of the shapes

  !> A closed tube: the polygon's vertices (counter-clockwise), corners rounded on the
  !! centreline by radius rc with chords of at most `dl` [m].
  pure subroutine section_tube(vert, t, rc, dl, s)
    real(wp), intent(in) :: vert(:,:)      !! vertices (2, nv) [m]
    real(wp), intent(in) :: t, rc, dl      !! thickness, corner radius, chord length [m]
    type(section_t), intent(out) :: s
    integer :: nv, i, k, na, n, m
    real(wp) :: a(2), b(2), c(2), u1(2), u2(2), turn, back, cen(2), ang0, dang, ang
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: side(:)
    nv = size(vert, 2)
    allocate(x(2, 0), side(0))
    do i = 1, nv
      a = vert(:, 1 + modulo(i - 2, nv))
      b = vert(:, i)
      c = vert(:, 1 + modulo(i, nv))
      u1 = (b - a)/norm2(b - a)
      u2 = (c - b)/norm2(c - b)
      turn = atan2(u1(1)*u2(2) - u1(2)*u2(1), dot_product(u1, u2))   ! > 0 left (convex)
      if (rc <= 0.0_wp .or. abs(turn) < 1.0e-12_wp) then
        x = reshape([x, b], [2, size(x, 2) + 1])
        side = [side, i]
        cycle
      end if
      back = rc*tan(0.5_wp*abs(turn))       ! the arc's ends, back from the vertex
      cen = b - back*u1 + sign(rc, turn)*[-u1(2), u1(1)]
      ang0 = atan2(b(2) - back*u1(2) - cen(2), b(1) - back*u1(1) - cen(1))
      na = max(1, ceiling(rc*abs(turn)/dl))
      dang = turn/real(na, wp)
      do k = 0, na
        ang = ang0 + dang*real(k, wp)
        x = reshape([x, cen + rc*[cos(ang), sin(ang)]], [2, size(x, 2) + 1])
        side = [side, merge(i - 1, i, 2*k < na)]      ! first half: the side before
      end do
    end do
    n = size(x, 2)
    s%nn = n
    s%ne = n
    s%xn = x
    allocate(s%en(2, n), s%et(n), s%ew(n))
    do k = 1, n
      m = 1 + modulo(k, n)
      s%en(:, k) = [k, m]
      s%et(k) = t
      ! the logical wall of edge k -> k+1: the side of its end points (a side's own straight
      ! edge joins two points of that side; an arc's chords the side whose half they are in)
      s%ew(k) = 1 + modulo(side(k) - 1, nv)
      if (side(k) /= side(m)) s%ew(k) = 1 + modulo(max(side(k), side(m)) - 1, nv)
    end do
    ! sharp corners: the straight edge from vertex i to i+1 is side i
    if (rc <= 0.0_wp) s%ew = [(k, k = 1, n)]
  end subroutine section_tube

  !> A panel of nx x ny hexagonal (angle > 0) or re-entrant (angle < 0) cells: inclined walls
  !! of length l at `angle` to x, vertical walls of length h; rows offset by half a cell;
  !! centred on `center`.
  pure subroutine section_honeycomb(ncell, l, h, angle_deg, t, center, s)
    integer, intent(in) :: ncell(2)        !! cells along x and y
    real(wp), intent(in) :: l, h           !! inclined and vertical wall lengths [m]
    real(wp), intent(in) :: angle_deg      !! the inclined walls' angle to x [degrees]
    real(wp), intent(in) :: t              !! thickness [m]
    real(wp), intent(in) :: center(2)      !! panel centre [m]
    type(section_t), intent(out) :: s
    real(wp) :: th, w, dy, cc(2), v(2, 6), lo(2), hi(2)
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: e(:,:)
    integer :: i, j, k, id(6), nn, ne, a, b
    th = angle_deg*pi/180.0_wp
    w = 2.0_wp*l*cos(th)
    dy = h + l*sin(th)
    allocate(x(2, 6*ncell(1)*ncell(2)), e(2, 6*ncell(1)*ncell(2)))
    nn = 0
    ne = 0
    do j = 0, ncell(2) - 1
      do i = 0, ncell(1) - 1
        cc = [w*(real(i, wp) + 0.5_wp*real(mod(j, 2), wp)), dy*real(j, wp)]
        ! counter-clockwise from the lower right: the vertical walls at x = +-w/2
        v(:, 1) = cc + [0.5_wp*w, -0.5_wp*h]
        v(:, 2) = cc + [0.5_wp*w, 0.5_wp*h]
        v(:, 3) = cc + [0.0_wp, 0.5_wp*h + l*sin(th)]
        v(:, 4) = cc + [-0.5_wp*w, 0.5_wp*h]
        v(:, 5) = cc + [-0.5_wp*w, -0.5_wp*h]
        v(:, 6) = cc + [0.0_wp, -0.5_wp*h - l*sin(th)]
        do k = 1, 6
          id(k) = find_node(x, nn, v(:, k), 1.0e-9_wp*l)
          if (id(k) == 0) then
            nn = nn + 1
            x(:, nn) = v(:, k)
            id(k) = nn
          end if
        end do
        do k = 1, 6
          a = id(k)
          b = id(1 + mod(k, 6))
          if (any((e(1, 1:ne) == a .and. e(2, 1:ne) == b) .or. &
                  (e(1, 1:ne) == b .and. e(2, 1:ne) == a))) cycle
          ne = ne + 1
          e(:, ne) = [a, b]
        end do
      end do
    end do
    lo = minval(x(:, 1:nn), dim=2)
    hi = maxval(x(:, 1:nn), dim=2)
    s%nn = nn
    s%ne = ne
    s%xn = x(:, 1:nn)
    do k = 1, nn
      s%xn(:, k) = s%xn(:, k) - 0.5_wp*(lo + hi) + center
    end do
    s%en = e(:, 1:ne)
    allocate(s%et(ne), s%ew(ne))
    s%et = t
    s%ew = [(k, k = 1, ne)]
  end subroutine section_honeycomb

  !> Any wall graph: segments (x1, y1, x2, y2, t) (5, ns); ends closer than tol are one node.
  pure subroutine section_walls(seg, tol, s)
    real(wp), intent(in) :: seg(:,:)       !! the segments (5, ns) [m]
    real(wp), intent(in) :: tol            !! ends closer than this are one joint [m]
    type(section_t), intent(out) :: s
    real(wp), allocatable :: x(:,:)
    integer :: k, ns, nn, a, b
    ns = size(seg, 2)
    allocate(x(2, 2*ns), s%en(2, ns), s%et(ns), s%ew(ns))
    nn = 0
    do k = 1, ns
      a = find_node(x, nn, seg(1:2, k), tol)
      if (a == 0) then
        nn = nn + 1
        x(:, nn) = seg(1:2, k)
        a = nn
      end if
      b = find_node(x, nn, seg(3:4, k), tol)
      if (b == 0) then
        nn = nn + 1
        x(:, nn) = seg(3:4, k)
        b = nn
      end if
      s%en(:, k) = [a, b]
      s%et(k) = seg(5, k)
      s%ew(k) = k
    end do
    s%nn = nn
    s%ne = ns
    s%xn = x(:, 1:nn)
  end subroutine section_walls

  !> Keep the part of the walls on the side (x - c) . n >= 0 of a mirror plane: a wall that
  !! crosses it is cut there, walls behind it are dropped. The section must be its own mirror
  !! image (each wall's image a wall of the same thickness), and every wall that reaches the
  !! plane must meet it square, so that the cut end lies in the plane; a wall along the plane
  !! is refused (half its thickness lies behind it). The logical walls keep their ids (the
  !! colours of self-contact are those of the whole section).
  pure subroutine section_clip(s, c, n, stat, msg)
    type(section_t), intent(inout) :: s    !! the walls
    real(wp), intent(in) :: c(2), n(2)     !! a point of the plane, its unit normal
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    real(wp), allocatable :: x(:,:), et(:)
    integer, allocatable :: en(:,:), ew(:)
    integer :: k, a, b, nn, ne, m
    real(wp) :: da, db, tol, u(2), xm(2)
    stat = 0
    msg = ''
    tol = 1.0e-9_wp*maxval(abs(s%xn))
    if (.not. mirror_symmetric(s, c, n, tol)) then
      stat = 1
      msg = 'the section is not its own mirror image about a plane'
      return
    end if
    x = s%xn
    nn = s%nn
    allocate(en(2, 0), et(0), ew(0))
    ne = 0
    do k = 1, s%ne
      a = s%en(1, k)
      b = s%en(2, k)
      da = dot_product(s%xn(:, a) - c, n)
      db = dot_product(s%xn(:, b) - c, n)
      u = (s%xn(:, b) - s%xn(:, a))/norm2(s%xn(:, b) - s%xn(:, a))
      if ((abs(da) <= tol .or. abs(db) <= tol .or. da*db < 0.0_wp) .and. &
          abs(abs(dot_product(u, n)) - 1.0_wp) > 1.0e-9_wp) then
        stat = 1
        msg = trim(merge('a wall lies along a plane       ', &
                         'a wall meets a plane at an angle', abs(da) <= tol .and. abs(db) <= tol))
        return
      end if
      if (da >= -tol .and. db >= -tol) then
        continue                                              ! on the kept side
      else if (da <= tol .and. db <= tol) then
        cycle                                                 ! behind the plane
      else
        xm = s%xn(:, a) + (s%xn(:, b) - s%xn(:, a))*(da/(da - db))
        xm = xm - dot_product(xm - c, n)*n                    ! exactly in the plane
        m = find_node(x, nn, xm, tol)
        if (m == 0) then
          x = reshape([x(:, 1:nn), xm], [2, nn + 1])
          nn = nn + 1
          m = nn
        end if
        if (da < 0.0_wp) a = m
        if (db < 0.0_wp) b = m
      end if
      en = reshape([en, a, b], [2, ne + 1])
      et = [et, s%et(k)]
      ew = [ew, s%ew(k)]
      ne = ne + 1
    end do
    if (ne == 0) then
      stat = 1
      msg = 'no wall lies on the modelled side of the mirror plane'
      return
    end if
    s%nn = nn
    s%xn = x(:, 1:nn)
    s%ne = ne
    s%en = en
    s%et = et
    s%ew = ew
  end subroutine section_clip

  !> stat 3 with msg when two walls' centrelines meet other than at a node they share: walls
  !! that cross, or a wall's end on another's length (a joint needs both split there).
  pure subroutine crossings(s, stat, msg)
    type(section_t), intent(in) :: s
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    real(wp) :: a(2), b(2), c(2), d(2), r(2), u(2), den, ta, tb, tol, x(2)
    character(len=24) :: at
    integer :: i, j
    stat = 0
    msg = ''
    tol = 1.0e-9_wp
    do i = 1, s%ne - 1
      a = s%xn(:, s%en(1, i))
      b = s%xn(:, s%en(2, i))
      do j = i + 1, s%ne
        if (any(s%en(:, j) == s%en(1, i)) .or. any(s%en(:, j) == s%en(2, i))) cycle
        c = s%xn(:, s%en(1, j))
        d = s%xn(:, s%en(2, j))
        if (max(a(1), b(1)) < min(c(1), d(1)) .or. max(c(1), d(1)) < min(a(1), b(1)) .or. &
            max(a(2), b(2)) < min(c(2), d(2)) .or. max(c(2), d(2)) < min(a(2), b(2))) cycle
        r = b - a
        u = d - c
        den = r(1)*u(2) - r(2)*u(1)
        if (abs(den) <= tol*norm2(r)*norm2(u)) cycle       ! parallel: apart (boxes may touch)
        ta = ((c(1) - a(1))*u(2) - (c(2) - a(2))*u(1))/den
        tb = ((c(1) - a(1))*r(2) - (c(2) - a(2))*r(1))/den
        if (ta < -tol .or. ta > 1.0_wp + tol .or. tb < -tol .or. tb > 1.0_wp + tol) cycle
        x = a + ta*r
        at = sci(x(1), 3)//', '//sci(x(2), 3)
        stat = 3
        msg = 'two walls meet at ('//trim(adjustl(at))//') m without a joint: split both '// &
              'there, so that walls meet only at their ends'
        return
      end do
    end do
  end subroutine crossings

  !> Whether each wall's mirror image about the plane through c of unit normal n is a wall
  !! of the section with the same thickness (to tol in position).
  pure logical function mirror_symmetric(s, c, n, tol) result(ok)
    type(section_t), intent(in) :: s
    real(wp), intent(in) :: c(2), n(2), tol
    real(wp) :: pa(2), pb(2), qa(2), qb(2)
    integer :: k, j
    ok = .false.
    do k = 1, s%ne
      pa = s%xn(:, s%en(1, k))
      pb = s%xn(:, s%en(2, k))
      pa = pa - 2.0_wp*dot_product(pa - c, n)*n
      pb = pb - 2.0_wp*dot_product(pb - c, n)*n
      do j = 1, s%ne
        qa = s%xn(:, s%en(1, j))
        qb = s%xn(:, s%en(2, j))
        if (abs(s%et(j) - s%et(k)) > 1.0e-9_wp*s%et(k)) cycle
        if ((norm2(qa - pa) <= tol .and. norm2(qb - pb) <= tol) .or. &
            (norm2(qa - pb) <= tol .and. norm2(qb - pa) <= tol)) exit
      end do
      if (j > s%ne) return
    end do
    ok = .true.
  end function mirror_symmetric

  !> The node of x(:, 1:n) within tol of p, or 0.
  pure integer function find_node(x, n, p, tol) result(id)
    real(wp), intent(in) :: x(:,:), p(2), tol
    integer, intent(in) :: n
    integer :: k
    id = 0
    do k = 1, n
      if (abs(x(1, k) - p(1)) <= tol .and. abs(x(2, k) - p(2)) <= tol) then
        id = k
        return
      end if
    end do
  end function find_node

  !> Centreline length of the walls [m].
  pure real(wp) function section_length(s) result(len_c)
    type(section_t), intent(in) :: s
    integer :: k
    len_c = 0.0_wp
    do k = 1, s%ne
      len_c = len_c + norm2(s%xn(:, s%en(2, k)) - s%xn(:, s%en(1, k)))
    end do
  end function section_length

  ! ------------------------------------------------------------------------ the particles

  !> The particles of a section: corners xc (2, nc), each particle's four corners (4, np,
  !! counter-clockwise) and its wall (the logical wall of its strip; a joint core: that of
  !! its first wall). stat /= 0 with msg when the walls cannot be meshed (a wall shorter
  !! than its joints need, walls meeting at too sharp an angle, n_thick odd at a Y joint);
  !! stat 3 when two walls cross or touch other than at a joint.
  pure subroutine section_mesh(s, n_thick, xc, quad, pwall, stat, msg)
    type(section_t), intent(in) :: s       !! the wall graph
    integer, intent(in) :: n_thick         !! particles through each wall
    real(wp), allocatable, intent(out) :: xc(:,:)  !! corners (2, nc) [m]
    integer, allocatable, intent(out) :: quad(:,:) !! corners of each particle (4, np)
    integer, allocatable, intent(out) :: pwall(:)  !! logical wall of each particle (np)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    real(wp), allocatable :: cut(:,:,:)    ! along-distance of each wall's face ends:
                                           ! (right/left face, start/end, wall), from node 1
    real(wp), allocatable :: pts(:,:), q(:,:,:)
    integer, allocatable :: qw(:), ids(:)
    integer :: nq
    stat = 0
    msg = ''
    allocate(cut(2, 2, s%ne), q(2, 4, 64), qw(64))
    nq = 0
    call crossings(s, stat, msg)
    if (stat /= 0) return
    call joint_cuts(s, cut, stat, msg)
    if (stat /= 0) return
    call strips(s, n_thick, cut, q, qw, nq, stat, msg)
    if (stat /= 0) return
    call cores(s, n_thick, cut, q, qw, nq, stat, msg)
    if (stat /= 0) return
    pts = reshape(q(:, :, 1:nq), [2, 4*nq])
    call merge_points(pts, 1.0e-9_wp*minval(s%et), xc, ids)
    quad = reshape(ids, [4, nq])
    pwall = qw(1:nq)
  end subroutine section_mesh

  !> Where each wall's faces end at its two nodes (along-distance from its first node).
  pure subroutine joint_cuts(s, cut, stat, msg)
    type(section_t), intent(in) :: s
    real(wp), intent(out) :: cut(:,:,:)    !! (face 1 right / 2 left, end 1 / 2, wall)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    integer :: nd, k, i, j, e1, e2, deg, inc(max_deg), ends(max_deg)
    real(wp) :: ang(max_deg), d1(2), d2(2), gap, sa, sb, len_e
    logical :: open_side(2, 2, s%ne)
    stat = 0
    msg = ''
    do k = 1, s%ne                          ! free: square cuts at both nodes
      cut(:, 1, k) = 0.0_wp
      cut(:, 2, k) = norm2(s%xn(:, s%en(2, k)) - s%xn(:, s%en(1, k)))
    end do
    open_side = .false.
    do nd = 1, s%nn
      call incident(s, nd, deg, inc, ends, ang)
      if (deg == 0) cycle
      if (deg > max_deg) then
        stat = 1
        msg = 'more than '//itoa(max_deg)//' walls meet at one joint'
        return
      end if
      if (deg == 1) cycle                   ! a free end: square cut at the node
      do i = 1, deg
        j = 1 + mod(i, deg)                 ! the next wall counter-clockwise
        e1 = inc(i)
        e2 = inc(j)
        gap = modulo(ang(j) - ang(i), 2.0_wp*pi)
        if (gap < 1.0e-6_wp .or. gap > 2.0_wp*pi - 1.0e-6_wp) then
          stat = 1
          msg = 'two walls leave the joint at ('//sci(s%xn(1, nd), 3)//', '// &
            sci(s%xn(2, nd), 3)//') m in the same direction (they overlap)'
          return
        end if
        d1 = out_dir(s, e1, ends(i))
        d2 = out_dir(s, e2, ends(j))
        ! the face of wall i on its left (seen outward from the node) meets the right face of
        ! wall j, (t/2) / tan(gap/2) out from the node (behind it for a gap over 180 degrees),
        ! unless they are parallel (a straight wall through the joint)
        if (abs(gap - pi) > 1.0e-9_wp) then
          call face_meet(d1, 0.5_wp*s%et(e1), d2, 0.5_wp*s%et(e2), sa, sb)
          call set_cut(cut, s, e1, ends(i), 2, sa)
          call set_cut(cut, s, e2, ends(j), 1, sb)
        else
          call mark_open(open_side, e1, ends(i), 2)
          call mark_open(open_side, e2, ends(j), 1)
        end if
      end do
    end do
    ! an open face ends across from the wall's other face (square when both are open)
    do k = 1, s%ne
      do j = 1, 2
        if (open_side(1, j, k) .and. .not. open_side(2, j, k)) cut(1, j, k) = cut(2, j, k)
        if (open_side(2, j, k) .and. .not. open_side(1, j, k)) cut(2, j, k) = cut(1, j, k)
      end do
      len_e = norm2(s%xn(:, s%en(2, k)) - s%xn(:, s%en(1, k)))
      if (any(cut(:, 2, k) - cut(:, 1, k) <= 0.05_wp*s%et(k))) then
        stat = 1
        msg = 'wall '//itoa(k)//' (length '//sci(len_e, 3)//' m) is too short '// &
          'for the joints at its ends: its faces end before they begin (walls meeting at too '// &
          'sharp an angle, or thicker than the wall is long)'
        return
      end if
    end do
  contains
    pure subroutine mark_open(op, e, end_, face)
      logical, intent(inout) :: op(:,:,:)
      integer, intent(in) :: e, end_, face
      integer :: f
      f = face                              ! faces seen outward from the node: at the end
      if (end_ == 2) f = 3 - face           ! node the wall's own left and right swap
      op(f, end_, e) = .true.
    end subroutine mark_open
  end subroutine joint_cuts

  !> Store the along-distance sa (outward from the node, face seen outward) of wall e's end.
  pure subroutine set_cut(cut, s, e, end_, face, sa)
    real(wp), intent(inout) :: cut(:,:,:)
    type(section_t), intent(in) :: s
    integer, intent(in) :: e, end_, face
    real(wp), intent(in) :: sa
    real(wp) :: len_e
    if (end_ == 1) then
      cut(face, 1, e) = sa
    else
      len_e = norm2(s%xn(:, s%en(2, e)) - s%xn(:, s%en(1, e)))
      cut(3 - face, 2, e) = len_e - sa
    end if
  end subroutine set_cut

  !> The walls at node nd, sorted counter-clockwise by the angle of their outward direction;
  !! ends(i) = 1 when the node is the wall's first node, 2 its second.
  pure subroutine incident(s, nd, deg, inc, ends, ang)
    type(section_t), intent(in) :: s
    integer, intent(in) :: nd
    integer, intent(out) :: deg, inc(max_deg), ends(max_deg)
    real(wp), intent(out) :: ang(max_deg)
    integer :: k, j, i, ti
    real(wp) :: d(2), ta
    deg = 0
    do k = 1, s%ne
      do j = 1, 2
        if (s%en(j, k) /= nd) cycle
        deg = deg + 1
        if (deg > max_deg) return
        inc(deg) = k
        ends(deg) = j
        d = out_dir(s, k, j)
        ang(deg) = atan2(d(2), d(1))
      end do
    end do
    do i = 2, deg                           ! insertion sort by angle
      ta = ang(i)
      ti = inc(i)
      j = ends(i)
      k = i - 1
      do while (k >= 1)
        if (ang(k) <= ta) exit
        ang(k + 1) = ang(k)
        inc(k + 1) = inc(k)
        ends(k + 1) = ends(k)
        k = k - 1
      end do
      ang(k + 1) = ta
      inc(k + 1) = ti
      ends(k + 1) = j
    end do
  end subroutine incident

  !> Unit direction of wall e pointing away from its end `end_`.
  pure function out_dir(s, e, end_) result(d)
    type(section_t), intent(in) :: s
    integer, intent(in) :: e, end_
    real(wp) :: d(2)
    d = s%xn(:, s%en(2, e)) - s%xn(:, s%en(1, e))
    if (end_ == 2) d = -d
    d = d/norm2(d)
  end function out_dir

  !> Where the left face (at +ha) of a wall leaving a node along d1 meets the right face (at -hb)
  !! of a wall leaving along d2: the along-distances sa on the first, sb on the second.
  pure subroutine face_meet(d1, ha, d2, hb, sa, sb)
    real(wp), intent(in) :: d1(2), ha, d2(2), hb
    real(wp), intent(out) :: sa, sb
    real(wp) :: n1(2), n2(2), r(2), det
    n1 = [-d1(2), d1(1)]
    n2 = [-d2(2), d2(1)]
    ! x0 + ha n1 + sa d1 = x0 - hb n2 + sb d2
    r = -hb*n2 - ha*n1
    det = d1(1)*(-d2(2)) - (-d2(1))*d1(2)
    sa = (r(1)*(-d2(2)) - (-d2(1))*r(2))/det
    sb = (d1(1)*r(2) - d1(2)*r(1))/det
  end subroutine face_meet

  !> The strip particles of every wall.
  pure subroutine strips(s, n_thick, cut, q, qw, nq, stat, msg)
    type(section_t), intent(in) :: s
    integer, intent(in) :: n_thick
    real(wp), intent(in) :: cut(:,:,:)
    real(wp), allocatable, intent(inout) :: q(:,:,:)
    integer, allocatable, intent(inout) :: qw(:)
    integer, intent(inout) :: nq
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    integer :: k, i, j, na
    real(wp) :: xa(2), u(2), nl(2), t, len_e, rs(2), ls(2), re(2), le(2), p(2, 4)
    stat = 0
    msg = ''
    do k = 1, s%ne
      xa = s%xn(:, s%en(1, k))
      u = s%xn(:, s%en(2, k)) - xa
      len_e = norm2(u)
      u = u/len_e
      nl = [-u(2), u(1)]
      t = s%et(k)
      rs = xa - 0.5_wp*t*nl + cut(1, 1, k)*u
      ls = xa + 0.5_wp*t*nl + cut(2, 1, k)*u
      re = xa - 0.5_wp*t*nl + cut(1, 2, k)*u
      le = xa + 0.5_wp*t*nl + cut(2, 2, k)*u
      na = max(1, nint(0.5_wp*(cut(1, 2, k) - cut(1, 1, k) + cut(2, 2, k) - cut(2, 1, k))/ &
                       (t/real(n_thick, wp))))
      do i = 0, na - 1
        do j = 0, n_thick - 1
          p(:, 1) = strip_point(i, j)
          p(:, 2) = strip_point(i + 1, j)
          p(:, 3) = strip_point(i + 1, j + 1)
          p(:, 4) = strip_point(i, j + 1)
          call push_quad(q, qw, nq, p, s%ew(k))
        end do
      end do
    end do
  contains
    pure function strip_point(i, j) result(x)
      integer, intent(in) :: i, j
      real(wp) :: x(2), sg, et
      sg = real(i, wp)/real(na, wp)
      et = real(j, wp)/real(n_thick, wp)
      x = (1.0_wp - sg)*((1.0_wp - et)*rs + et*ls) + sg*((1.0_wp - et)*re + et*le)
    end function strip_point
  end subroutine strips

  !> The core particles of every joint of three or more walls.
  pure subroutine cores(s, n_thick, cut, q, qw, nq, stat, msg)
    type(section_t), intent(in) :: s
    integer, intent(in) :: n_thick
    real(wp), intent(in) :: cut(:,:,:)
    real(wp), allocatable, intent(inout) :: q(:,:,:)
    integer, allocatable, intent(inout) :: qw(:)
    integer, intent(inout) :: nq
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    integer :: nd, deg, inc(max_deg), ends(max_deg), i, m, a, b, nh
    real(wp) :: ang(max_deg), v(2, 2*max_deg), rr(2), ll(2), c(2), mids(2, 2*max_deg)
    stat = 0
    msg = ''
    do nd = 1, s%nn
      call incident(s, nd, deg, inc, ends, ang)
      if (deg < 3) cycle
      m = 0
      do i = 1, deg                        ! each wall's cut, right face then left (outward)
        call end_points(s, cut, inc(i), ends(i), rr, ll)
        if (m == 0) then
          m = m + 1
          v(:, m) = rr
        else if (norm2(rr - v(:, m)) > 1.0e-9_wp*s%et(inc(i))) then
          m = m + 1
          v(:, m) = rr
        end if
        m = m + 1
        v(:, m) = ll
      end do
      if (norm2(v(:, m) - v(:, 1)) <= 1.0e-9_wp*s%et(inc(1))) m = m - 1
      if (m == 4) then                     ! a quadrilateral: n x n
        call grid_quads(v(:, 1), v(:, 2), v(:, 3), v(:, 4), n_thick, n_thick, q, qw, nq, &
                        s%ew(inc(1)))
      else
        if (mod(n_thick, 2) /= 0) then
          stat = 1
          msg = itoa(deg)//' walls meet at ('//sci(s%xn(1, nd), 3)//', '// &
            sci(s%xn(2, nd), 3)//') m: such a joint needs an even n_thick'
          return
        end if
        nh = n_thick/2
        c = sum(v(:, 1:m), dim=2)/real(m, wp)
        do i = 1, m
          mids(:, i) = 0.5_wp*(v(:, i) + v(:, 1 + mod(i, m)))
        end do
        do i = 1, m
          a = i
          b = 1 + modulo(i - 2, m)
          call grid_quads(v(:, a), mids(:, a), c, mids(:, b), nh, nh, q, qw, nq, &
                          s%ew(inc(1)))
        end do
      end if
    end do
    do i = 1, nq
      if (quad_area(q(:, :, i)) <= 0.0_wp) then
        stat = 1
        msg = 'a joint''s particles turn inside out: walls meet at too sharp an angle for '// &
          'their thickness'
        return
      end if
    end do
  end subroutine cores

  !> A solid disc (a filler): an O-grid of a central square (corners at r/2) divided n x n
  !! and four blocks between its sides and the circle, n along and m = nint(0.9 n) out, the
  !! block's lines straight between the square and n points of the circle (its chords).
  !! The lines x = centre and y = centre are mesh lines (n is even), so `parts` = 2 keeps the
  !! particles of x >= centre (a half disc) and 4 those of x, y >= centre (a quarter) exactly.
  pure subroutine disc_mesh(center, r, n_radius, xc, quad, parts)
    real(wp), intent(in) :: center(2)      !! centre [m]
    real(wp), intent(in) :: r              !! radius [m]
    integer, intent(in) :: n_radius        !! particles along the radius (n = 2 ceiling(n/2))
    real(wp), allocatable, intent(out) :: xc(:,:)  !! corners (2, nc) [m]
    integer, allocatable, intent(out) :: quad(:,:) !! corners of each particle (4, np)
    integer, intent(in) :: parts           !! 1 the whole disc, 2 the half, 4 the quarter
    real(wp), allocatable :: q(:,:,:), pts(:,:)
    integer, allocatable :: qw(:), ids(:)
    integer :: nq, n, m, side, i, j, k
    real(wp) :: sq(2, 4), a0, p(2, 4), c(2)
    n = max(2, 2*((n_radius + 1)/2))
    m = max(1, nint(0.9_wp*real(n, wp)))
    allocate(q(2, 4, 64), qw(64))
    nq = 0
    do i = 1, 4                            ! the square's corners at 45, 135, 225, 315 degrees
      a0 = 0.25_wp*pi + 0.5_wp*pi*real(i - 1, wp)
      sq(:, i) = center + 0.5_wp*r*[cos(a0), sin(a0)]
    end do
    call grid_quads(sq(:, 3), sq(:, 4), sq(:, 1), sq(:, 2), n, n, q, qw, nq, 0)
    do side = 1, 4                         ! the block outside side (corner side -> side + 1)
      do j = 0, m - 1
        do i = 0, n - 1
          p(:, 1) = block_point(side, i, j)          ! out, then along: counter-clockwise
          p(:, 2) = block_point(side, i, j + 1)
          p(:, 3) = block_point(side, i + 1, j + 1)
          p(:, 4) = block_point(side, i + 1, j)
          call push_quad(q, qw, nq, p, 0)
        end do
      end do
    end do
    k = 0                                  ! the sector's particles (centroids off the lines)
    do i = 1, nq
      c = 0.25_wp*sum(q(:, :, i), dim=2) - center
      if ((parts >= 2 .and. c(1) < 0.0_wp) .or. (parts >= 4 .and. c(2) < 0.0_wp)) cycle
      k = k + 1
      q(:, :, k) = q(:, :, i)
    end do
    nq = k
    pts = reshape(q(:, :, 1:nq), [2, 4*nq])
    call merge_points(pts, 1.0e-9_wp*r, xc, ids)
    quad = reshape(ids, [4, nq])
  contains
    pure function block_point(side, i, j) result(x)
      integer, intent(in) :: side, i, j
      real(wp) :: x(2), s, e, ang, inner(2), outer(2)
      s = real(i, wp)/real(n, wp)
      e = real(j, wp)/real(m, wp)
      inner = (1.0_wp - s)*sq(:, side) + s*sq(:, 1 + mod(side, 4))
      ang = 0.25_wp*pi + 0.5_wp*pi*(real(side - 1, wp) + s)
      outer = center + r*[cos(ang), sin(ang)]
      x = (1.0_wp - e)*inner + e*outer
    end function block_point
  end subroutine disc_mesh

  !> The right and left face ends (seen outward from the node) of wall e at its end `end_`.
  pure subroutine end_points(s, cut, e, end_, rr, ll)
    type(section_t), intent(in) :: s
    real(wp), intent(in) :: cut(:,:,:)
    integer, intent(in) :: e, end_
    real(wp), intent(out) :: rr(2), ll(2)
    real(wp) :: xa(2), u(2), nl(2), t
    xa = s%xn(:, s%en(1, e))
    u = s%xn(:, s%en(2, e)) - xa
    u = u/norm2(u)
    nl = [-u(2), u(1)]
    t = s%et(e)
    if (end_ == 1) then
      rr = xa - 0.5_wp*t*nl + cut(1, 1, e)*u
      ll = xa + 0.5_wp*t*nl + cut(2, 1, e)*u
    else                                   ! outward from the second node: faces swap
      rr = xa + 0.5_wp*t*nl + cut(2, 2, e)*u
      ll = xa - 0.5_wp*t*nl + cut(1, 2, e)*u
    end if
  end subroutine end_points

  !> The n1 x n2 bilinear division of the quadrilateral p1 p2 p3 p4 (counter-clockwise).
  pure subroutine grid_quads(p1, p2, p3, p4, n1, n2, q, qw, nq, wall)
    real(wp), intent(in) :: p1(2), p2(2), p3(2), p4(2)
    integer, intent(in) :: n1, n2, wall
    real(wp), allocatable, intent(inout) :: q(:,:,:)
    integer, allocatable, intent(inout) :: qw(:)
    integer, intent(inout) :: nq
    integer :: i, j
    real(wp) :: p(2, 4)
    do j = 0, n2 - 1
      do i = 0, n1 - 1
        p(:, 1) = bil(i, j)
        p(:, 2) = bil(i + 1, j)
        p(:, 3) = bil(i + 1, j + 1)
        p(:, 4) = bil(i, j + 1)
        call push_quad(q, qw, nq, p, wall)
      end do
    end do
  contains
    pure function bil(i, j) result(x)
      integer, intent(in) :: i, j
      real(wp) :: x(2), a, b
      a = real(i, wp)/real(n1, wp)
      b = real(j, wp)/real(n2, wp)
      x = (1.0_wp - b)*((1.0_wp - a)*p1 + a*p2) + b*((1.0_wp - a)*p4 + a*p3)
    end function bil
  end subroutine grid_quads

  !> Append a quadrilateral.
  pure subroutine push_quad(q, qw, nq, p, wall)
    real(wp), allocatable, intent(inout) :: q(:,:,:)
    integer, allocatable, intent(inout) :: qw(:)
    integer, intent(inout) :: nq
    real(wp), intent(in) :: p(2, 4)
    integer, intent(in) :: wall
    real(wp), allocatable :: t(:,:,:)
    integer, allocatable :: tw(:)
    if (nq == size(q, 3)) then
      allocate(t(2, 4, 2*nq), tw(2*nq))
      t(:, :, 1:nq) = q(:, :, 1:nq)
      tw(1:nq) = qw(1:nq)
      call move_alloc(t, q)
      call move_alloc(tw, qw)
    end if
    nq = nq + 1
    q(:, :, nq) = p
    qw(nq) = wall
  end subroutine push_quad

  !> Signed area of a quadrilateral (shoelace).
  pure real(wp) function quad_area(p) result(a)
    real(wp), intent(in) :: p(2, 4)
    integer :: k, m
    a = 0.0_wp
    do k = 1, 4
      m = 1 + mod(k, 4)
      a = a + p(1, k)*p(2, m) - p(1, m)*p(2, k)
    end do
    a = 0.5_wp*a
  end function quad_area

  !> Summed area of the particles [m^2].
  pure real(wp) function section_area(xc, quad) result(a)
    real(wp), intent(in) :: xc(:,:)
    integer, intent(in) :: quad(:,:)
    integer :: k
    a = 0.0_wp
    do k = 1, size(quad, 2)
      a = a + quad_area(xc(:, quad(:, k)))
    end do
  end function section_area

end module mpm_sections
