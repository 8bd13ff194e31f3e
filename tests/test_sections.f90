!> The section mesher (mpm_sections) against closed forms and an independent point test:
!! - the summed particle area against the section's closed form: a tube with mitred corners
!!   has exactly t times its centreline length (the outer offset polygon less the inner one:
!!   A + P t/2 + c - (A - P t/2 + c)); a regular honeycomb (angle 30, h = l) has t times its
!!   wall length less (sqrt(3)/4) t^2 for each Y joint (three strips cut t/(2 sqrt 3) from the
!!   node, plus the equilateral core of side t); the centroid of a symmetric section at its
!!   centre;
!! - no gap and no overlap: points sampled at random in the union of the walls' rectangles
!!   (node to node, width t; with only Y joints and free ends that union is the mitred section)
!!   each lie in exactly one particle, and points just outside every wall in none;
!! - every particle counter-clockwise (positive area) and the corners shared (each inner edge
!!   of one particle is the reverse edge of another: the boundary is one closed chain per face
!!   of the tube);
!! - the wall colours: opposite walls of a square tube differ, and so do non-adjacent walls of
!!   a cell;
!! - a disc (the filler's O-grid): the area of its chords' polygon, and its half and quarter
!!   (sector) a half and a quarter of the whole, every particle on the kept side of the planes.
! SPDX-License-Identifier: MIT
program test_sections
  use mpm_kinds, only: wp
  use mpm_constants, only: pi
  use mpm_sections, only: section_t, section_tube, section_honeycomb, section_walls, &
                          section_clip, section_mesh, section_area, section_length, disc_mesh
  use mpm_section_colours, only: section_colours
  use testing, only: begin_test, check, check_close, finish_tests
  use testing_sim, only: inside_count
  use mpm_strings, only: itoa, rtoa
  implicit none
  type(section_t) :: s
  real(wp), allocatable :: xc(:,:), seg(:,:)
  integer, allocatable :: quad(:,:), pw(:), col(:)
  integer :: stat, ncol, k, parts, np_whole, i, j
  character(len=:), allocatable :: msg
  real(wp) :: a, t, c(2), area_whole

  call begin_test('square tube, sharp corners')
  a = 0.048_wp
  t = 1.5e-3_wp
  call section_tube(reshape([0.0_wp, 0.0_wp, a, 0.0_wp, a, a, 0.0_wp, a], [2, 4]), t, &
                    0.0_wp, t/4.0_wp, s)
  call section_mesh(s, 4, xc, quad, pw, stat, msg)
  call check(stat == 0, 'meshed: '//msg)
  call check_close(section_area(xc, quad), 4.0_wp*a*t, 'area = 4 a t', rtol=1.0e-12_wp)
  call centroid(xc, quad, c)
  call check_close(c, [0.5_wp*a, 0.5_wp*a], 'centroid at the centre', atol=1.0e-12_wp*a)
  call check(count(edge_count(quad) == 1) == 2*(4*nint(a/(t/4.0_wp)) + 4) .or. &
             closed_boundary(quad), 'boundary: two closed chains')
  call sample(s, xc, quad, 4000)
  call section_colours(s, col, ncol)
  call check(ncol == 2 .and. col(1) /= col(3) .and. col(2) /= col(4), &
             'opposite walls in different colours')

  call begin_test('square tube, rounded corners')
  call section_tube(reshape([0.0_wp, 0.0_wp, a, 0.0_wp, a, a, 0.0_wp, a], [2, 4]), t, &
                    3.0e-3_wp, t/4.0_wp, s)
  call section_mesh(s, 4, xc, quad, pw, stat, msg)
  call check(stat == 0, 'meshed: '//msg)
  ! the chords' polygon: t times its own centreline length (mitred at each chord's joint)
  call check_close(section_area(xc, quad), t*section_length(s), 'area = t L (chords)', &
                   rtol=1.0e-12_wp)
  ! and the chords are within (1 - cos(dphi/2)) of the arc: t (4 (a - 2 rc) + 2 pi rc)
  call check_close(section_area(xc, quad), t*(4.0_wp*(a - 2.0_wp*3.0e-3_wp) + &
                   2.0_wp*pi*3.0e-3_wp), 'area = t L (arcs), chords within 1e-3', &
                   rtol=1.0e-3_wp)
  call check(closed_boundary(quad), 'boundary: closed chains')
  call section_colours(s, col, ncol)
  call check(ncol == 2 .and. col(1) /= col(3) .and. col(2) /= col(4), &
             'opposite sides in different colours')

  call begin_test('hexagonal tube')
  call section_tube(reshape([(0.02_wp*cos(pi/3.0_wp*k), 0.02_wp*sin(pi/3.0_wp*k), &
                    k = 0, 5)], [2, 6]), 1.0e-3_wp, 0.0_wp, 0.25e-3_wp, s)
  call section_mesh(s, 3, xc, quad, pw, stat, msg)
  call check(stat == 0, 'meshed: '//msg)
  call check_close(section_area(xc, quad), 6.0_wp*0.02_wp*1.0e-3_wp, 'area = 6 s t', &
                   rtol=1.0e-12_wp)

  call begin_test('regular honeycomb (Y joints)')
  t = 0.5e-3_wp
  call section_honeycomb([3, 3], 5.0e-3_wp, 5.0e-3_wp, 30.0_wp, t, [0.0_wp, 0.0_wp], s)
  call section_mesh(s, 2, xc, quad, pw, stat, msg)
  call check(stat == 0, 'meshed: '//msg)
  call check_close(section_area(xc, quad), t*section_length(s) - &
                   sqrt(3.0_wp)/4.0_wp*t**2*real(count(degree(s) == 3), wp), &
                   'area = t L - sqrt(3)/4 t^2 per Y joint', rtol=1.0e-12_wp)
  call sample(s, xc, quad, 6000)
  call check(all(abs(quad_areas(xc, quad)) > 0.0_wp) .and. all(quad_areas(xc, quad) > 0.0_wp), &
             'every particle counter-clockwise')
  call section_colours(s, col, ncol)
  call check(cells_apart(s, col), 'non-adjacent walls of a cell in different colours')
  call check(ncol <= 6, 'at most 6 colours')

  call begin_test('re-entrant honeycomb')
  call section_honeycomb([3, 2], 5.0e-3_wp, 10.0e-3_wp, -30.0_wp, t, [0.0_wp, 0.0_wp], s)
  call section_mesh(s, 2, xc, quad, pw, stat, msg)
  call check(stat == 0, 'meshed: '//msg)
  call sample(s, xc, quad, 6000)
  call check(all(quad_areas(xc, quad) > 0.0_wp), 'every particle counter-clockwise')

  call begin_test('2 x 2 multi-cell tube from segments (T and X joints)')
  a = 0.02_wp
  allocate(seg(5, 12))
  do k = 0, 1
    seg(:, 1 + k) = [k*a, 0.0_wp, (k + 1)*a, 0.0_wp, 1.0e-3_wp]            ! bottom
    seg(:, 3 + k) = [k*a, 2*a, (k + 1)*a, 2*a, 1.0e-3_wp]                  ! top
    seg(:, 5 + k) = [0.0_wp, k*a, 0.0_wp, (k + 1)*a, 1.0e-3_wp]            ! left
    seg(:, 7 + k) = [2*a, k*a, 2*a, (k + 1)*a, 1.0e-3_wp]                  ! right
    seg(:, 9 + k) = [k*a, a, (k + 1)*a, a, 1.0e-3_wp]                      ! web along x
    seg(:, 11 + k) = [a, k*a, a, (k + 1)*a, 1.0e-3_wp]                     ! web along y
  end do
  call section_walls(seg, 1.0e-9_wp, s)
  call section_mesh(s, 3, xc, quad, pw, stat, msg)
  call check(stat == 0, 'meshed with odd n_thick: '//msg)
  ! outer square 4 (2a) t, two webs 2 (2a - t) t less their crossing t^2
  call check_close(section_area(xc, quad), 8.0_wp*a*1.0e-3_wp + 2.0_wp*(2.0_wp*a - &
                   1.0e-3_wp)*1.0e-3_wp - 1.0e-6_wp, 'area: closed form', rtol=1.0e-12_wp)
  call check(closed_boundary(quad), 'boundary: closed chains')
  call section_colours(s, col, ncol)
  call check(cells_apart(s, col), 'non-adjacent walls of a cell in different colours')

  call begin_test('disc: whole, half and quarter')
  ! the boundary is 4 n chords of the circle (n = 10 for n_thick 9, rounded up to even)
  do parts = 1, 4
    if (parts == 3) cycle
    call disc_mesh([1.0e-3_wp, 2.0e-3_wp], 0.01_wp, 9, xc, quad, parts)
    if (parts == 1) np_whole = size(quad, 2)
    call check(size(quad, 2)*parts == np_whole, 'particles: the whole disc''s / parts')
    call check_close(section_area(xc, quad)*real(parts, wp), 0.5_wp*40.0_wp*0.01_wp**2* &
                     sin(2.0_wp*pi/40.0_wp), 'area x parts = the 40-gon''s', rtol=1.0e-12_wp)
    call check(all(quad_areas(xc, quad) > 0.0_wp), 'every particle counter-clockwise')
    call check(closed_boundary(quad), 'boundary: one closed chain')
    if (parts >= 2) call check(minval(xc(1, :)) > 1.0e-3_wp - 1.0e-12_wp, 'x >= centre')
    if (parts == 4) call check(minval(xc(2, :)) > 2.0e-3_wp - 1.0e-12_wp, 'y >= centre')
  end do

  call begin_test('walls: a 3 x 3 multi-cell tube, half and quarter')
  ! outer square 3a, two webs each way; the planes through its centre cut walls square
  deallocate(seg)
  allocate(seg(5, 24))
  k = 0
  do i = 0, 2
    do j = 0, 3
      k = k + 1
      seg(:, k) = [i*a, j*a, (i + 1)*a, j*a, 1.0e-3_wp]                    ! along x
      k = k + 1
      seg(:, k) = [j*a, i*a, j*a, (i + 1)*a, 1.0e-3_wp]                    ! along y
    end do
  end do
  call section_walls(seg, 1.0e-9_wp, s)
  call section_mesh(s, 4, xc, quad, pw, stat, msg)
  area_whole = section_area(xc, quad)
  ! mitred outer square 12 a t, four webs (3a - t) t each, less their 4 crossings: 24 a t - 8 t^2
  call check(stat == 0, 'whole meshed: '//msg)
  call check_close(area_whole, 24.0_wp*a*1.0e-3_wp - 8.0e-6_wp, 'whole: 24 a t - 8 t^2', &
                   rtol=1.0e-12_wp)
  do parts = 2, 4, 2
    call section_walls(seg, 1.0e-9_wp, s)
    call section_clip(s, [1.5_wp*a, 1.5_wp*a], [1.0_wp, 0.0_wp], stat, msg)
    call check(stat == 0, 'half: clipped: '//msg)
    if (parts == 4) then
      call section_clip(s, [1.5_wp*a, 1.5_wp*a], [0.0_wp, 1.0_wp], stat, msg)
      call check(stat == 0, 'quarter: clipped: '//msg)
    end if
    call section_mesh(s, 4, xc, quad, pw, stat, msg)
    call check(stat == 0, 'sector meshed: '//msg)
    call check_close(section_area(xc, quad)*real(parts, wp), area_whole, &
                     'area x parts = the whole''s', rtol=1.0e-12_wp)
    call check(minval(xc(1, :)) > 1.5_wp*a - 1.0e-12_wp, 'x >= centre')
    if (parts == 4) call check(minval(xc(2, :)) > 1.5_wp*a - 1.0e-12_wp, 'y >= centre')
  end do

  call begin_test('sectors refused')
  call section_walls(seg, 1.0e-9_wp, s)                  ! 3 x 3 about a wall: not symmetric
  call section_clip(s, [a, 1.5_wp*a], [1.0_wp, 0.0_wp], stat, msg)
  call check(stat /= 0 .and. index(msg, 'not its own mirror image') > 0, 'an asymmetric section: '//msg)
  call section_walls(reshape([0.0_wp, 0.0_wp, 2*a, 0.0_wp, 1.0e-3_wp, &
                              0.0_wp, 2*a, 2*a, 2*a, 1.0e-3_wp, &
                              0.0_wp, 0.0_wp, 0.0_wp, 2*a, 1.0e-3_wp, &
                              2*a, 0.0_wp, 2*a, 2*a, 1.0e-3_wp, &
                              a, 0.0_wp, a, 2*a, 1.0e-3_wp], [5, 5]), 1.0e-9_wp, s)  ! 2 x 1
  call section_clip(s, [a, a], [1.0_wp, 0.0_wp], stat, msg)
  call check(stat /= 0 .and. index(msg, 'along a plane') > 0, &
             'a web along the plane: '//msg)
  call section_tube(reshape([0.0_wp, -a, a, 0.0_wp, 0.0_wp, a, -a, 0.0_wp], [2, 4]), &
                    1.0e-3_wp, 0.0_wp, 1.0e-3_wp, s)    ! a diamond: corners on the plane
  call section_clip(s, [0.0_wp, 0.0_wp], [1.0_wp, 0.0_wp], stat, msg)
  call check(stat /= 0 .and. index(msg, 'at an angle') > 0, 'a corner on the plane: '//msg)

  call begin_test('walls that cross without a joint')
  call section_walls(reshape([0.0_wp, 0.0_wp, 2*a, 0.0_wp, 1.0e-3_wp, &
                              a, -a, a, a, 1.0e-3_wp], [5, 2]), 1.0e-9_wp, s)   ! a plus
  call section_mesh(s, 4, xc, quad, pw, stat, msg)
  call check(stat == 3 .and. index(msg, 'without a joint') > 0, 'crossing walls: '//msg)
  call section_walls(reshape([0.0_wp, 0.0_wp, 2*a, 0.0_wp, 1.0e-3_wp, &
                              a, 0.0_wp, a, a, 1.0e-3_wp], [5, 2]), 1.0e-9_wp, s)   ! a T
  call section_mesh(s, 4, xc, quad, pw, stat, msg)
  call check(stat == 3, 'a wall ending on another''s length: '//msg)
  call section_walls(reshape([0.0_wp, 0.0_wp, a, 0.0_wp, 1.0e-3_wp, &
                              a, 0.0_wp, 2*a, 0.0_wp, 1.0e-3_wp, &
                              a, 0.0_wp, a, a, 1.0e-3_wp], [5, 3]), 1.0e-9_wp, s)   ! split T
  call section_mesh(s, 4, xc, quad, pw, stat, msg)
  call check(stat == 0, 'the same T split at the joint meshes: '//msg)

  call begin_test('bad sections')
  call section_walls(reshape([0.0_wp, 0.0_wp, 1.0e-3_wp, 0.0_wp, 2.0e-3_wp, &
                              1.0e-3_wp, 0.0_wp, 0.0_wp, 0.5e-3_wp, 2.0e-3_wp], [5, 2]), &
                     1.0e-9_wp, s)
  call section_mesh(s, 2, xc, quad, pw, stat, msg)
  call check(stat /= 0 .and. index(msg, 'too short') > 0, 'a sharp, thick joint refused: '//msg)
  call section_honeycomb([2, 2], 5.0e-3_wp, 5.0e-3_wp, 30.0_wp, 0.5e-3_wp, [0.0_wp, 0.0_wp], s)
  call section_mesh(s, 3, xc, quad, pw, stat, msg)
  call check(stat /= 0 .and. index(msg, 'even n_thick') > 0, 'odd n_thick at a Y refused: '//msg)

  call finish_tests('test_sections')

contains

  function quad_areas(xc, quad) result(ar)
    real(wp), intent(in) :: xc(:,:)
    integer, intent(in) :: quad(:,:)
    real(wp) :: ar(size(quad, 2))
    integer :: k
    do k = 1, size(quad, 2)
      ar(k) = section_area(xc, quad(:, k:k))
    end do
  end function quad_areas

  subroutine centroid(xc, quad, c)
    real(wp), intent(in) :: xc(:,:)
    integer, intent(in) :: quad(:,:)
    real(wp), intent(out) :: c(2)
    real(wp) :: ar(size(quad, 2))
    integer :: k
    ar = quad_areas(xc, quad)
    c = 0.0_wp
    do k = 1, size(quad, 2)            ! area-weighted corner mean: exact for symmetric sets
      c = c + ar(k)*0.25_wp*sum(xc(:, quad(:, k)), dim=2)
    end do
    c = c/sum(ar)
  end subroutine centroid

  !> How many particles have each directed edge (a, b) or (b, a): 1 on the boundary.
  function edge_count(quad) result(n)
    integer, intent(in) :: quad(:,:)
    integer :: n(4*size(quad, 2))
    integer :: k, j, m, i, a, b
    n = 0
    do k = 1, size(quad, 2)
      do j = 1, 4
        a = quad(j, k)
        b = quad(1 + mod(j, 4), k)
        do m = 1, size(quad, 2)
          do i = 1, 4
            if (quad(i, m) == b .and. quad(1 + mod(i, 4), m) == a) n(4*(k - 1) + j) = &
              n(4*(k - 1) + j) + 1
          end do
        end do
        n(4*(k - 1) + j) = n(4*(k - 1) + j) + 1
      end do
    end do
  end function edge_count

  !> Every corner on the boundary has exactly one boundary edge in and one out.
  logical function closed_boundary(quad) result(ok)
    integer, intent(in) :: quad(:,:)
    integer :: n(4*size(quad, 2)), nin(maxval(quad)), nout(maxval(quad)), k, j
    n = edge_count(quad)
    nin = 0
    nout = 0
    do k = 1, size(quad, 2)
      do j = 1, 4
        if (n(4*(k - 1) + j) /= 1) cycle
        nout(quad(j, k)) = nout(quad(j, k)) + 1
        nin(quad(1 + mod(j, 4), k)) = nin(quad(1 + mod(j, 4), k)) + 1
      end do
    end do
    ok = all(nin == nout) .and. all(nin <= 1) .and. count(n == 1) > 0
  end function closed_boundary

  function degree(s) result(d)
    type(section_t), intent(in) :: s
    integer :: d(s%nn), k
    d = 0
    do k = 1, s%ne
      d(s%en(:, k)) = d(s%en(:, k)) + 1
    end do
  end function degree

  !> Non-adjacent walls within one cell's reach (their midpoints closer than the largest
  !! wall length plus a bit, and no shared node) take different colours, where both walls
  !! bound a common cell: tested on the pairs whose midpoints are within one wall length.
  logical function cells_apart(s, col) result(ok)
    type(section_t), intent(in) :: s
    integer, intent(in) :: col(:)
    integer :: i, j
    real(wp) :: mi(2), mj(2), lmax
    lmax = 0.0_wp
    do i = 1, s%ne
      lmax = max(lmax, norm2(s%xn(:, s%en(2, i)) - s%xn(:, s%en(1, i))))
    end do
    ok = .true.
    do i = 1, s%ne
      do j = i + 1, s%ne
        if (any(s%en(:, i) == s%en(1, j)) .or. any(s%en(:, i) == s%en(2, j))) cycle
        mi = 0.5_wp*(s%xn(:, s%en(1, i)) + s%xn(:, s%en(2, i)))
        mj = 0.5_wp*(s%xn(:, s%en(1, j)) + s%xn(:, s%en(2, j)))
        ! opposite walls of a hexagonal cell: midpoints about 2 l cos(30) apart
        if (norm2(mi - mj) < 0.9_wp*lmax .and. col(i) == col(j)) ok = .false.
      end do
    end do
  end function cells_apart

  !> Random points in the union of the wall rectangles lie in exactly one particle; points
  !! at 1.02 t/2 from a wall's centreline (beyond the node-to-node span's ends excluded) and
  !! outside every other wall's rectangle lie in none.
  subroutine sample(s, xc, quad, n)
    type(section_t), intent(in) :: s
    real(wp), intent(in) :: xc(:,:)
    integer, intent(in) :: quad(:,:), n
    integer :: k, e, hits, bad_in, bad_out, tried_out
    real(wp) :: r(3), xa(2), u(2), nl(2), len_e, p(2)
    bad_in = 0
    bad_out = 0
    tried_out = 0
    call random_seed()
    do k = 1, n
      call random_number(r)
      e = 1 + min(s%ne - 1, int(r(1)*s%ne))
      xa = s%xn(:, s%en(1, e))
      u = s%xn(:, s%en(2, e)) - xa
      len_e = norm2(u)
      u = u/len_e
      nl = [-u(2), u(1)]
      p = xa + r(2)*len_e*u + (r(3) - 0.5_wp)*s%et(e)*nl
      hits = inside_count(xc, quad, p)
      if (hits /= 1) bad_in = bad_in + 1
      p = xa + r(2)*len_e*u + sign(0.51_wp, r(3) - 0.5_wp)*s%et(e)*nl
      if (in_any_wall(s, p)) cycle
      tried_out = tried_out + 1
      if (inside_count(xc, quad, p) /= 0) bad_out = bad_out + 1
    end do
    call check(bad_in == 0, 'no gap, no overlap: '//itoa(bad_in)//' of '//itoa(n)// &
               ' points inside the walls not in exactly one particle')
    call check(bad_out == 0 .and. tried_out > n/4, 'nothing outside: '//itoa(bad_out)// &
               ' of '//itoa(tried_out)//' points outside the walls in a particle')
  end subroutine sample

  logical function in_any_wall(s, p) result(inside)
    type(section_t), intent(in) :: s
    real(wp), intent(in) :: p(2)
    integer :: e
    real(wp) :: xa(2), u(2), len_e, al, ac
    inside = .false.
    do e = 1, s%ne
      xa = s%xn(:, s%en(1, e))
      u = s%xn(:, s%en(2, e)) - xa
      len_e = norm2(u)
      u = u/len_e
      al = dot_product(p - xa, u)
      ac = dot_product(p - xa, [-u(2), u(1)])
      ! its rectangle, grown by the mitre's reach at a corner (t/2 each way)
      if (al >= -0.5_wp*s%et(e) .and. al <= len_e + 0.5_wp*s%et(e) .and. &
          abs(ac) <= 0.5_wp*s%et(e)*1.0001_wp) inside = .true.
    end do
  end function in_any_wall
end program test_sections
