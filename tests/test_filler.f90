!> The filler of a tube (mpm_sections, filler_mesh) against closed forms and an independent
!! point test:
!! - the summed particle area against the closed form of the tube's inner face moved in by the
!!   gap: a polygon of area A0 and perimeter P0 offset inwards by d (mitred) has the area
!!   A0 - d P0 + d^2 sum tan(phi_i/2) (phi_i its turns); for a square tube of centreline side a
!!   with sharp corners that is (a - t - 2 gap)^2, with corners rounded by chords (na per
!!   corner, documented in docs/method.md) A0 and P0 are the chords' polygon's;
!! - the half and the quarter: a half and a quarter of the whole, every corner on the kept side;
!! - no gap and no overlap: points sampled at random in the inner face (computed here, from the
!!   documented geometry) each lie in exactly one particle, points outside it in none; with no
!!   gap, points in the tube's outer face lie in exactly one particle of the tube and the
!!   filler together (the filler's boundary is the tube's inner face);
!! - every particle counter-clockwise, and every vertex of the inner face a corner;
!! - refusals: a gap that closes an edge (at the closed form's largest gap), a non-convex
!!   inner face.
! SPDX-License-Identifier: MIT
program test_filler
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: pi
  use mpm_sections, only: section_t, section_tube, section_mesh, section_area
  use mpm_filler, only: filler_mesh
  use testing, only: begin_test, check, check_close, finish_tests
  use testing_sim, only: inside_count
  use mpm_strings, only: itoa
  implicit none
  real(wp), parameter :: a = 0.048_wp, t = 1.5e-3_wp, rc = 3.0e-3_wp
  real(wp) :: sq(2, 4), hex(2, 6), gap, area_full, d
  real(wp), allocatable :: xc(:,:), poly(:,:)
  integer, allocatable :: quad(:,:)
  integer :: stat, parts, k, n_thick
  integer(i8) :: seed = 12345_i8
  character(len=:), allocatable :: msg

  sq = reshape([-0.5_wp*a, -0.5_wp*a, 0.5_wp*a, -0.5_wp*a, 0.5_wp*a, 0.5_wp*a, -0.5_wp*a, &
                0.5_wp*a], [2, 4])
  n_thick = 4                              ! the tube's: chords of t / 4

  call begin_test('square tube, sharp corners: area (a - t - 2 gap)^2')
  do k = 0, 1
    gap = 0.3e-3_wp*real(k, wp)
    do parts = 1, 4
      if (parts == 3) cycle
      call filler_mesh(sq, t, 0.0_wp, t/real(n_thick, wp), gap, [0.0_wp, 0.0_wp], parts, 20, &
                       xc, quad, stat, msg)
      call check(stat == 0, 'meshed: '//msg)
      call check_close(section_area(xc, quad)*real(parts, wp), (a - t - 2.0_wp*gap)**2, &
                       'gap '//rtoa(gap)//', parts '//itoa(parts)//': area x parts', &
                       rtol=1.0e-13_wp)
      poly = inner_face(sq, 0.0_wp, gap)
      call particle_checks(xc, quad, poly, parts, 'sharp, gap '//rtoa(gap)//', parts '// &
                           itoa(parts))
    end do
  end do

  call begin_test('square tube, rounded corners (chords): area of the offset chord polygon')
  do k = 0, 1
    gap = 0.3e-3_wp*real(k, wp)
    do parts = 1, 4
      if (parts == 3) cycle
      call filler_mesh(sq, t, rc, t/real(n_thick, wp), gap, [0.0_wp, 0.0_wp], parts, 20, &
                       xc, quad, stat, msg)
      call check(stat == 0, 'meshed: '//msg)
      d = 0.5_wp*t + gap
      area_full = rounded_square_area(a, rc, t/real(n_thick, wp), d)
      call check_close(section_area(xc, quad)*real(parts, wp), area_full, &
                       'gap '//rtoa(gap)//', parts '//itoa(parts)//': area x parts', &
                       rtol=1.0e-13_wp)
      poly = inner_face(sq, rc, gap)
      call check_close(polygon_area(poly), area_full, 'the sampled polygon''s area', &
                       rtol=1.0e-13_wp)
      call particle_checks(xc, quad, poly, parts, 'rounded, gap '//rtoa(gap)//', parts '// &
                           itoa(parts))
    end do
  end do
  ! and the chords are within a per mille of the arcs: (a - t)^2 - (4 - pi) (rc - t/2)^2
  call check_close(rounded_square_area(a, rc, t/real(n_thick, wp), 0.5_wp*t), &
                   (a - t)**2 - (4.0_wp - pi)*(rc - 0.5_wp*t)**2, 'chords near the arcs', &
                   rtol=1.0e-3_wp)

  call begin_test('no gap: the filler and the tube tile the tube''s outer face')
  do parts = 1, 4
    if (parts == 3) cycle
    call filler_mesh(sq, t, rc, t/real(n_thick, wp), 0.0_wp, [0.0_wp, 0.0_wp], parts, 20, &
                     xc, quad, stat, msg)
    call together(xc, quad, parts)
  end do

  call begin_test('hexagonal tube (quarter): area 2 sqrt(3) (apothem - t/2 - gap)^2')
  do k = 0, 5
    hex(:, k + 1) = 0.02_wp*[cos(pi/3.0_wp*k), sin(pi/3.0_wp*k)]
  end do
  gap = 0.2e-3_wp
  call filler_mesh(hex, 1.0e-3_wp, 0.0_wp, 0.25e-3_wp, gap, [0.0_wp, 0.0_wp], 4, 16, xc, &
                   quad, stat, msg)
  call check(stat == 0, 'meshed: '//msg)
  call check_close(4.0_wp*section_area(xc, quad), 2.0_wp*sqrt(3.0_wp)*(0.02_wp*sqrt(3.0_wp)/ &
                   2.0_wp - 0.5e-3_wp - gap)**2, 'area x 4', rtol=1.0e-13_wp)
  poly = inner_face(hex, 0.0_wp, gap, 0.5e-3_wp)
  call particle_checks(xc, quad, poly, 4, 'hexagon')

  call begin_test('refused: a gap that closes an edge, a non-convex inner face')
  ! sharp square: the inner face's edges (a - t) close at gap (a - t)/2
  call filler_mesh(sq, t, 0.0_wp, t, 0.5_wp*(a - t)*1.0001_wp, [0.0_wp, 0.0_wp], 1, 8, xc, &
                   quad, stat, msg)
  call check(stat /= 0 .and. index(msg, 'fill_gap') > 0 .and. index(msg, &
             trim(rtoa(0.5_wp*(a - t)))) > 0, 'gap above (a - t)/2 refused, naming it: '//msg)
  call filler_mesh(sq, t, 0.0_wp, t, 0.5_wp*(a - t)*0.999_wp, [0.0_wp, 0.0_wp], 1, 8, xc, &
                   quad, stat, msg)
  call check(stat == 0, 'gap just below (a - t)/2 meshed: '//msg)
  ! an arrow: (0,0) (2,1) (0,2) (1,1) turns inwards at (1,1)
  call filler_mesh(0.01_wp*reshape([0.0_wp, 0.0_wp, 2.0_wp, 1.0_wp, 0.0_wp, 2.0_wp, &
                   0.8_wp, 1.0_wp], [2, 4]), 1.0e-3_wp, 0.0_wp, 0.25e-3_wp, 0.0_wp, &
                   [0.0_wp, 0.0_wp], 1, 8, xc, quad, stat, msg)
  call check(stat /= 0 .and. index(msg, 'convex') > 0, 'non-convex refused: '//msg)

  call finish_tests('test_filler')

contains

  !> Particles counter-clockwise; the sampled tiling of poly (the kept part of it); every
  !! vertex of poly on the kept side a corner.
  subroutine particle_checks(xc, quad, poly, parts, what)
    real(wp), intent(in) :: xc(:,:), poly(:,:)
    integer, intent(in) :: quad(:,:), parts
    character(len=*), intent(in) :: what
    integer :: k, n, bad_in, bad_out, n_in, n_out, missing
    real(wp) :: lo(2), hi(2), r(2), p(2)
    call check(all(quad_areas(xc, quad) > 0.0_wp), what//': every particle counter-clockwise')
    if (parts >= 2) call check(minval(xc(1, :)) >= -1.0e-12_wp, what//': x >= centre')
    if (parts >= 4) call check(minval(xc(2, :)) >= -1.0e-12_wp, what//': y >= centre')
    missing = 0
    do k = 1, size(poly, 2)
      if (parts >= 2 .and. poly(1, k) < 0.0_wp) cycle
      if (parts >= 4 .and. poly(2, k) < 0.0_wp) cycle
      if (minval(norm2(xc - spread(poly(:, k), 2, size(xc, 2)), dim=1)) > 1.0e-12_wp) &
        missing = missing + 1
    end do
    call check(missing == 0, what//': every vertex of the inner face a corner ('// &
               itoa(missing)//' missing)')
    lo = minval(poly, dim=2) - 0.05_wp*a
    hi = maxval(poly, dim=2) + 0.05_wp*a
    if (parts >= 2) lo(1) = 0.0_wp
    if (parts >= 4) lo(2) = 0.0_wp
    bad_in = 0
    bad_out = 0
    n_in = 0
    n_out = 0
    do k = 1, 3000
      r = [uniform(), uniform()]
      p = lo + r*(hi - lo)
      n = inside_count(xc, quad, p)
      if (in_polygon(poly, p, 1.0e-9_wp*a)) then
        n_in = n_in + 1
        if (n /= 1) bad_in = bad_in + 1
      else if (.not. in_polygon(poly, p, -1.0e-9_wp*a)) then
        n_out = n_out + 1
        if (n /= 0) bad_out = bad_out + 1
      end if
    end do
    call check(bad_in == 0 .and. n_in > 1000, what//': '//itoa(bad_in)//' of '//itoa(n_in)// &
               ' points in the inner face not in exactly one particle')
    call check(bad_out == 0 .and. n_out > 100, what//': '//itoa(bad_out)//' of '// &
               itoa(n_out)//' points outside it in a particle')
  end subroutine particle_checks

  !> Points in the tube's outer face (a point of the kept part) lie in exactly one particle of
  !! the tube (section_mesh of the tube, its sector cut here by centroids) and the filler.
  subroutine together(xf, qf, parts)
    real(wp), intent(in) :: xf(:,:)
    integer, intent(in) :: qf(:,:), parts
    type(section_t) :: s
    real(wp), allocatable :: xt(:,:), outer(:,:)
    integer, allocatable :: qt(:,:), pw(:), keep(:)
    integer :: k, n, bad, n_in, stat2
    real(wp) :: p(2), c(2)
    character(len=:), allocatable :: msg2
    call section_tube(sq, t, rc, t/real(n_thick, wp), s)
    call section_mesh(s, n_thick, xt, qt, pw, stat2, msg2)
    call check(stat2 == 0, 'the tube meshed: '//msg2)
    allocate(keep(0))
    do k = 1, size(qt, 2)                  ! the tube's particles of the kept part
      c = 0.25_wp*sum(xt(:, qt(:, k)), dim=2)
      if ((parts >= 2 .and. c(1) < 0.0_wp) .or. (parts >= 4 .and. c(2) < 0.0_wp)) cycle
      keep = [keep, k]
    end do
    outer = inner_face(sq, rc, -t)         ! the outer face: the inner one moved out by t
    bad = 0
    n_in = 0
    do k = 1, 4000
      p = (0.5_wp*a + t)*[2.0_wp*uniform() - 1.0_wp, 2.0_wp*uniform() - 1.0_wp]
      if (parts >= 2) p(1) = abs(p(1))
      if (parts >= 4) p(2) = abs(p(2))
      if (.not. in_polygon(outer, p, 1.0e-9_wp*a)) cycle
      n_in = n_in + 1
      n = inside_count(xf, qf, p) + inside_count(xt, qt(:, keep), p)
      if (n /= 1) bad = bad + 1
    end do
    call check(bad == 0 .and. n_in > 2000, 'parts '//itoa(parts)//': '//itoa(bad)//' of '// &
               itoa(n_in)//' points in the outer face not in exactly one particle of the '// &
               'tube and the filler')
  end subroutine together

  !> The inner face of a tube of centreline vert, corners rounded by chords of the arcs of
  !! radius r (docs/method.md: ceiling(r phi / (t / n_thick)) chords for a turn phi), moved in
  !! by th/2 + gap (mitred): computed here from the documented geometry.
  function inner_face(vert, r, gap, half_t) result(poly)
    real(wp), intent(in) :: vert(:,:), r, gap
    real(wp), intent(in), optional :: half_t
    real(wp), allocatable :: poly(:,:)
    real(wp), allocatable :: cl(:,:)
    real(wp) :: u1(2), u2(2), turn, back, cen(2), a0, dang, n1(2), n2(2), dd
    integer :: i, nv, k, na
    nv = size(vert, 2)
    allocate(cl(2, 0))
    do i = 1, nv
      u1 = vert(:, i) - vert(:, 1 + modulo(i - 2, nv))
      u1 = u1/norm2(u1)
      u2 = vert(:, 1 + mod(i, nv)) - vert(:, i)
      u2 = u2/norm2(u2)
      turn = atan2(u1(1)*u2(2) - u1(2)*u2(1), dot_product(u1, u2))
      if (r <= 0.0_wp) then
        cl = reshape([cl, vert(:, i)], [2, size(cl, 2) + 1])
        cycle
      end if
      back = r*tan(0.5_wp*turn)
      cen = vert(:, i) - back*u1 + r*[-u1(2), u1(1)]
      a0 = atan2(u1(1), -u1(2)) - pi          ! the arc starts at cen - r (left normal)
      na = ceiling(r*turn/(t/real(n_thick, wp)))
      dang = turn/real(na, wp)
      do k = 0, na
        cl = reshape([cl, cen + r*[cos(a0 + dang*k), sin(a0 + dang*k)]], [2, size(cl, 2) + 1])
      end do
    end do
    dd = 0.5_wp*t + gap
    if (present(half_t)) dd = half_t + gap
    nv = size(cl, 2)
    allocate(poly(2, nv))
    do i = 1, nv
      u1 = cl(:, i) - cl(:, 1 + modulo(i - 2, nv))
      u1 = u1/norm2(u1)
      u2 = cl(:, 1 + mod(i, nv)) - cl(:, i)
      u2 = u2/norm2(u2)
      n1 = [-u1(2), u1(1)]
      n2 = [-u2(2), u2(1)]
      poly(:, i) = cl(:, i) + dd*(n1 + n2)/(1.0_wp + dot_product(n1, n2))
    end do
  end function inner_face

  !> The closed form of a square of centreline side s with corners rounded by na chords of
  !! radius r (na = ceiling(r (pi/2) / dl)) moved in by d: A0 - d P0 + d^2 sum tan(phi/2).
  pure real(wp) function rounded_square_area(s, r, dl, d) result(ar)
    real(wp), intent(in) :: s, r, dl, d
    real(wp) :: dphi, a0, p0, tsum
    integer :: na
    na = ceiling(r*0.5_wp*pi/dl)
    dphi = 0.5_wp*pi/real(na, wp)
    a0 = s**2 - 4.0_wp*r**2 + 4.0_wp*real(na, wp)*0.5_wp*r**2*sin(dphi)
    p0 = 4.0_wp*(s - 2.0_wp*r) + 4.0_wp*real(na, wp)*2.0_wp*r*sin(0.5_wp*dphi)
    ! turns: half a chord's at each end of an arc, a whole one between its chords
    tsum = 4.0_wp*(2.0_wp*tan(0.25_wp*dphi) + real(na - 1, wp)*tan(0.5_wp*dphi))
    ar = a0 - d*p0 + d**2*tsum
  end function rounded_square_area

  pure real(wp) function polygon_area(p) result(ar)
    real(wp), intent(in) :: p(:,:)
    ar = 0.5_wp*sum(p(1, :)*cshift(p(2, :), 1) - cshift(p(1, :), 1)*p(2, :))
  end function polygon_area

  !> p left of every edge of the convex counter-clockwise polygon by more than tol.
  pure logical function in_polygon(poly, p, tol) result(inside)
    real(wp), intent(in) :: poly(:,:), p(2), tol
    integer :: k, kn
    real(wp) :: e(2)
    inside = .true.
    do k = 1, size(poly, 2)
      kn = 1 + mod(k, size(poly, 2))
      e = poly(:, kn) - poly(:, k)
      if ((e(1)*(p(2) - poly(2, k)) - e(2)*(p(1) - poly(1, k)))/norm2(e) <= tol) &
        inside = .false.
    end do
  end function in_polygon

  function quad_areas(xc, quad) result(ar)
    real(wp), intent(in) :: xc(:,:)
    integer, intent(in) :: quad(:,:)
    real(wp) :: ar(size(quad, 2))
    integer :: k
    do k = 1, size(quad, 2)
      ar(k) = polygon_area(xc(:, quad(:, k)))
    end do
  end function quad_areas

  !> A uniform number in [0, 1) (a linear congruential generator: the same points every run).
  real(wp) function uniform()
    seed = modulo(seed*16807_i8, 2147483647_i8)
    uniform = real(seed, wp)/2147483647.0_wp
  end function uniform

  !> A length as the filler's messages write it (es10.3).
  function rtoa(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=16) :: b
    write(b, '(es10.3)') x
    s = trim(adjustl(b))
  end function rtoa
end program test_filler
