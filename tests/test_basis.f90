!> Tests of mpm_basis: reproducing properties of every basis, block layout and `need`,
!> uGIMP against brute-force averages and finite differences, CPDI2 against Gauss quadrature,
!> cross-checks between the bases, and the CPDI2 quad geometry.
! SPDX-License-Identifier: MIT
!
! Positions in the property checks are taken in units of h relative to node (i0, j0), so the
! tolerance 1e-12 is absolute in units where h = 1 (sum_i x_i (x) gw_i = I is unchanged by the
! shift because sum_i gw_i = 0, which is checked on its own).
program test_basis
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_value, ieee_quiet_nan, &
                                           ieee_positive_inf, ieee_negative_inf
  use, intrinsic :: ieee_exceptions, only: ieee_flag_type, ieee_invalid, ieee_overflow, &
                                           ieee_divide_by_zero, ieee_underflow, &
                                           ieee_get_halting_mode, ieee_set_halting_mode, &
                                           ieee_set_flag
  use mpm_kinds, only: wp
  use mpm_constants, only: pi, BASIS_LINEAR, BASIS_UGIMP, BASIS_CPDI1, BASIS_CPDI2
  use mpm_basis, only: weights_linear, weights_ugimp, weights_cpdi1, weights_cpdi2, cpdi2_geometry, &
                       bilinear_at, cpdi2_folded, cpdi2_first_folded
  use mpm_particles, only: basis_block
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none

  integer, parameter :: K_LINEAR = 1, K_UGIMP = 2, K_CPDI1 = 3, K_CPDI2 = 4
  integer, parameter :: nbig = 8          ! block width for the reference calls
  integer, parameter :: nrand = 300       ! random particles per set
  real(wp), parameter :: tol = 1.0e-12_wp
  real(wp) :: origin(2), h
  real(wp), allocatable :: pars(:, :)
  integer :: n, k

  call set_seed()

  ! Main grid: binary-exact origin and h, so that "on a node" and "on an edge" are exact.
  origin = [-0.375_wp, 0.25_wp]
  h = 1.0_wp

  call test_bilinear_at()
  call test_linear()
  call test_ugimp()
  call test_cpdi1()
  call test_cpdi2()
  call test_geometry()
  call test_folded()

  ! Scaled grid (h not a power of two, origin away from zero): the random sets again.
  origin = [1.7_wp, -3.3_wp]
  h = 0.0125_wp
  n = nrand
  allocate(pars(8, n))
  do k = 1, n
    call random_linear(pars(:, k))
  end do
  call run_set(K_LINEAR, 'scaled grid, linear', pars, .false.)
  do k = 1, n
    call random_ugimp(0.05_wp, 0.5_wp, pars(:, k))
  end do
  call run_set(K_UGIMP, 'scaled grid, ugimp', pars, .true.)
  do k = 1, n
    call random_parallelogram(0.05_wp, 0.25_wp, pars(:, k))
  end do
  call run_set(K_CPDI1, 'scaled grid, cpdi1', pars, .false.)
  do k = 1, n
    call random_convex_quad(0.1_wp, 0.45_wp, pars(:, k))
  end do
  call run_set(K_CPDI2, 'scaled grid, cpdi2', pars, .true.)
  call gauss_set('scaled grid, cpdi2 vs Gauss', pars)
  call test_block_width()

  call finish_tests('test_basis')

contains

  ! ---------------------------------------------------------------------------------------------
  ! basis_block (mpm_particles): the block width that mpm_weights starts from and mpm_budget
  ! estimates with holds what each basis routine says its particle needs, for domains up to
  ! the extent given (the bounding box of the domain, up to 3 cells), and the linear basis
  ! needs exactly its 2.
  subroutine test_block_width()
    integer, parameter :: basis_of(4) = [BASIS_LINEAR, BASIS_UGIMP, BASIS_CPDI1, BASIS_CPDI2]
    real(wp) :: p(8), xc(2, 4), w(nbig*nbig), gw(2, nbig*nbig), ext
    integer :: kind, k, i0, j0, need, nb, bad
    call begin_test('block width (basis_block)')
    call check(basis_block(BASIS_CPDI2, 0.0_wp, h) == 3, 'a domain basis starts at 3 nodes')
    do kind = K_LINEAR, K_CPDI2
      bad = 0
      do k = 1, nrand
        select case (kind)
        case (K_LINEAR); call random_linear(p)
        case (K_UGIMP); call random_ugimp(0.05_wp, 1.5_wp, p)
        case (K_CPDI1); call random_parallelogram(0.05_wp, 0.75_wp, p)
        case default; call random_convex_quad(0.1_wp, 1.5_wp, p)
        end select
        call eval_basis(kind, p, nbig, i0, j0, w, gw, need)
        select case (kind)
        case (K_LINEAR); ext = 0.0_wp
        case (K_UGIMP); ext = 2.0_wp*maxval(p(3:4))
        case (K_CPDI1); xc = corners_of(p)
        case default; xc = reshape(p, [2, 4])
        end select
        if (kind >= K_CPDI1) ext = max(maxval(xc(1, :)) - minval(xc(1, :)), &
                                       maxval(xc(2, :)) - minval(xc(2, :)))
        nb = basis_block(basis_of(kind), ext, h)
        if (need > nb .or. (kind == K_LINEAR .and. nb /= 2)) bad = bad + 1
      end do
      call check(bad == 0, 'kind '//achar(48 + kind)//': the block holds what the basis '// &
                 'needs (failures: '//achar(48 + min(bad, 9))//')')
    end do
  end subroutine test_block_width

  ! ---------------------------------------------------------------------------------------------
  ! Set-ups

  subroutine set_seed()
    integer :: ns, i
    integer, allocatable :: seed(:)
    call random_seed(size=ns)
    allocate(seed(ns))
    seed = [(20240611 + 7919*i, i = 1, ns)]
    call random_seed(put=seed)
  end subroutine set_seed

  ! Particle parameters p(8): linear/uGIMP: xp, half; CPDI1: xp, r1, r2; CPDI2: corners.
  subroutine random_linear(p)
    real(wp), intent(out) :: p(8)
    real(wp) :: r(2)
    call random_number(r)
    p = 0.0_wp
    p(1:2) = origin + h*(1.0_wp + 6.0_wp*r)
  end subroutine random_linear

  subroutine random_ugimp(hmin, hmax, p)
    real(wp), intent(in) :: hmin, hmax     ! range of half / h
    real(wp), intent(out) :: p(8)
    real(wp) :: r(4)
    call random_number(r)
    p = 0.0_wp
    p(1:2) = origin + h*(2.0_wp + 4.0_wp*r(1:2))
    p(3:4) = h*(hmin + (hmax - hmin)*r(3:4))
  end subroutine random_ugimp

  ! Sheared, stretched and rotated parallelogram: r_k = F r_k0 with det F > 0.
  subroutine random_parallelogram(lmin, lmax, p)
    real(wp), intent(in) :: lmin, lmax     ! range of the half lengths / h
    real(wp), intent(out) :: p(8)
    real(wp) :: r(7), th, phi, l1, l2
    call random_number(r)
    p(1:2) = origin + h*(2.0_wp + 4.0_wp*r(1:2))
    l1 = h*(lmin + (lmax - lmin)*r(3))
    l2 = h*(lmin + (lmax - lmin)*r(4))
    th = 2.0_wp*pi*r(5)
    phi = 0.25_wp + (pi - 0.5_wp)*r(6)          ! angle between r1 and r2 in (0.25, pi - 0.25)
    p(3:4) = l1*[cos(th), sin(th)]
    p(5:6) = l2*[cos(th + phi), sin(th + phi)]
    p(7:8) = 0.0_wp
  end subroutine random_parallelogram

  ! Convex quad, counter-clockwise: four points of a rotated ellipse at increasing angles.
  subroutine random_convex_quad(amin, amax, p)
    real(wp), intent(in) :: amin, amax     ! range of the ellipse semi-axes / h
    real(wp), intent(out) :: p(8)
    real(wp) :: r(6), jit(4), c(2), ax, ay, rot, t, e(2)
    integer :: kc
    call random_number(r)
    call random_number(jit)
    c = origin + h*(2.0_wp + 4.0_wp*r(1:2))
    ax = h*(amin + (amax - amin)*r(3))
    ay = h*(amin + (amax - amin)*r(4))
    rot = 2.0_wp*pi*r(5)
    do kc = 1, 4
      t = 2.0_wp*pi*r(6) + real(kc - 1, wp)*0.5_wp*pi + 0.9_wp*(jit(kc) - 0.5_wp)
      e = [ax*cos(t), ay*sin(t)]
      p(2*kc - 1:2*kc) = c + [cos(rot)*e(1) - sin(rot)*e(2), sin(rot)*e(1) + cos(rot)*e(2)]
    end do
  end subroutine random_convex_quad

  ! Corners of the CPDI1 parallelogram (xp, r1, r2).
  function corners_of(p) result(xc)
    real(wp), intent(in) :: p(8)
    real(wp) :: xc(2, 4)
    xc(:, 1) = p(1:2) - p(3:4) - p(5:6)
    xc(:, 2) = p(1:2) + p(3:4) - p(5:6)
    xc(:, 3) = p(1:2) + p(3:4) + p(5:6)
    xc(:, 4) = p(1:2) - p(3:4) + p(5:6)
  end function corners_of

  ! ---------------------------------------------------------------------------------------------
  ! Generic evaluation and checks

  subroutine eval_basis(kind, p, nb, i0, j0, w, gw, need)
    integer, intent(in) :: kind, nb
    real(wp), intent(in) :: p(8)
    integer, intent(out) :: i0, j0, need
    real(wp), intent(out) :: w(nb*nb), gw(2, nb*nb)
    select case (kind)
    case (K_LINEAR)
      call weights_linear(p(1:2), origin, h, nb, i0, j0, w, gw, need)
    case (K_UGIMP)
      call weights_ugimp(p(1:2), p(3:4), origin, h, nb, i0, j0, w, gw, need)
    case (K_CPDI1)
      call weights_cpdi1(p(1:2), p(3:4), p(5:6), origin, h, nb, i0, j0, w, gw, need)
    case default
      call weights_cpdi2(reshape(p, [2, 4]), origin, h, nb, i0, j0, w, gw, need)
    end select
  end subroutine eval_basis

  ! The point sum_i phi_i x_i must reproduce: centre, or the area centroid for CPDI2.
  function ref_point(kind, p) result(x)
    integer, intent(in) :: kind
    real(wp), intent(in) :: p(8)
    real(wp) :: x(2), area, jmin
    if (kind == K_CPDI2) then
      call cpdi2_geometry(reshape(p, [2, 4]), area, x, jmin)
    else
      x = p(1:2)
    end if
  end function ref_point

  ! Largest errors of the four reproducing properties, in units where h = 1.
  subroutine add_props(w, gw, i0, j0, nb, xref, err)
    real(wp), intent(in) :: w(:), gw(:, :), xref(2)
    integer, intent(in) :: i0, j0, nb
    real(wp), intent(inout) :: err(4)
    real(wp) :: sw, sg(2), sx(2), m(2, 2), xl(2), sref(2)
    integer :: a, b, kk
    sw = 0.0_wp; sg = 0.0_wp; sx = 0.0_wp; m = 0.0_wp
    do b = 0, nb - 1
      do a = 0, nb - 1
        kk = 1 + a + nb*b
        xl = [real(a, wp), real(b, wp)]
        sw = sw + w(kk)
        sg = sg + gw(:, kk)*h
        sx = sx + w(kk)*xl
        m(:, 1) = m(:, 1) + xl*gw(1, kk)*h
        m(:, 2) = m(:, 2) + xl*gw(2, kk)*h
      end do
    end do
    sref = (xref - origin)/h - [real(i0, wp), real(j0, wp)]
    err(1) = max(err(1), abs(sw - 1.0_wp))
    err(2) = max(err(2), maxval(abs(sg)))
    err(3) = max(err(3), maxval(abs(sx - sref)))
    m(1, 1) = m(1, 1) - 1.0_wp
    m(2, 2) = m(2, 2) - 1.0_wp
    err(4) = max(err(4), maxval(abs(m)))
  end subroutine add_props

  subroutine report_props(label, err)
    character(len=*), intent(in) :: label
    real(wp), intent(in) :: err(4)
    call check_close(err(1), 0.0_wp, label//': sum w = 1', atol=tol)
    call check_close(err(2), 0.0_wp, label//': sum gw = 0', atol=tol)
    call check_close(err(3), 0.0_wp, label//': sum w x_i = x_p (centroid)', atol=tol)
    call check_close(err(4), 0.0_wp, label//': sum x_i (x) gw_i = I', atol=tol)
  end subroutine report_props

  ! Tight block: column 0 and row 0 are touched, the last touched column or row is need - 1,
  ! and everything beyond need is exactly zero.
  logical function is_tight(w, gw, nb, need)
    real(wp), intent(in) :: w(:), gw(:, :)
    integer, intent(in) :: nb, need
    integer :: a, b, kk, lastc, lastr
    logical :: col0, row0, outside_zero
    lastc = -1; lastr = -1; col0 = .false.; row0 = .false.; outside_zero = .true.
    do b = 0, nb - 1
      do a = 0, nb - 1
        kk = 1 + a + nb*b
        if (w(kk) /= 0.0_wp) then
          lastc = max(lastc, a)
          lastr = max(lastr, b)
          if (a == 0) col0 = .true.
          if (b == 0) row0 = .true.
        end if
        if (a >= need .or. b >= need) then
          if (w(kk) /= 0.0_wp .or. any(gw(:, kk) /= 0.0_wp)) outside_zero = .false.
        end if
      end do
    end do
    is_tight = col0 .and. row0 .and. max(lastc, lastr) + 1 == need .and. outside_zero
  end function is_tight

  ! Weight of global node (i, j) in a block result (0 outside the block).
  real(wp) function weight_at(i, j, i0, j0, nb, w)
    integer, intent(in) :: i, j, i0, j0, nb
    real(wp), intent(in) :: w(:)
    if (i < i0 .or. i >= i0 + nb .or. j < j0 .or. j >= j0 + nb) then
      weight_at = 0.0_wp
    else
      weight_at = w(1 + (i - i0) + nb*(j - j0))
    end if
  end function weight_at

  ! Reference checks for one set of particles: properties (nb = nbig), tightness, the same
  ! weights with nb = need, need <= 3 for small domains, and nb = need - 1 reports need > nb.
  subroutine run_set(kind, label, ps, small)
    integer, intent(in) :: kind
    character(len=*), intent(in) :: label
    real(wp), intent(in) :: ps(:, :)
    logical, intent(in) :: small            ! every domain is smaller than a cell
    real(wp) :: w(nbig*nbig), gw(2, nbig*nbig), err(4), errnb
    real(wp), allocatable :: w2(:), gw2(:, :)
    integer :: ip, i0, j0, need, i2, j2, need2, a, b, nbad_tight, nbad_need, nbad_small
    err = 0.0_wp; errnb = 0.0_wp
    nbad_tight = 0; nbad_need = 0; nbad_small = 0
    do ip = 1, size(ps, 2)
      call eval_basis(kind, ps(:, ip), nbig, i0, j0, w, gw, need)
      if (need > nbig) then
        nbad_need = nbad_need + 1
        cycle
      end if
      call add_props(w, gw, i0, j0, nbig, ref_point(kind, ps(:, ip)), err)
      if (kind /= K_LINEAR) then
        if (.not. is_tight(w, gw, nbig, need)) nbad_tight = nbad_tight + 1
      else
        if (need /= 2) nbad_need = nbad_need + 1
      end if
      if (small .and. need > 3) nbad_small = nbad_small + 1
      ! Same call with the smallest block: same lower-left node and the same numbers.
      allocate(w2(need*need), gw2(2, need*need))
      call eval_basis(kind, ps(:, ip), need, i2, j2, w2, gw2, need2)
      if (i2 /= i0 .or. j2 /= j0 .or. need2 /= need) nbad_need = nbad_need + 1
      do b = 0, need - 1
        do a = 0, need - 1
          errnb = max(errnb, abs(w2(1 + a + need*b) - w(1 + a + nbig*b)), &
                  h*maxval(abs(gw2(:, 1 + a + need*b) - gw(:, 1 + a + nbig*b))))
        end do
      end do
      deallocate(w2, gw2)
      ! A block one too small must be reported (the checks of -fcheck=all guard the bounds).
      allocate(w2((need - 1)**2), gw2(2, (need - 1)**2))
      call eval_basis(kind, ps(:, ip), need - 1, i2, j2, w2, gw2, need2)
      if (need2 /= need) nbad_need = nbad_need + 1
      deallocate(w2, gw2)
    end do
    call begin_test(label)
    call report_props(label, err)
    call check(nbad_need == 0, label//': need consistent for nb = 8, need, need - 1')
    if (kind /= K_LINEAR) call check(nbad_tight == 0, label//': block is the tightest one')
    if (small) call check(nbad_small == 0, label//': need <= 3 for domains below a cell')
    call check_close(errnb, 0.0_wp, label//': nb = need gives the same weights', atol=tol)
  end subroutine run_set

  ! ---------------------------------------------------------------------------------------------
  ! bilinear_at

  subroutine test_bilinear_at()
    real(wp) :: x(2), r(2), w4(4), s(2), e1, e2
    integer :: i0, j0, ip
    call begin_test('bilinear_at')
    e1 = 0.0_wp; e2 = 0.0_wp
    do ip = 1, nrand
      call random_number(r)
      x = origin + h*(1.0_wp + 6.0_wp*r)
      call bilinear_at(x, origin, h, i0, j0, w4)
      s = [w4(2) + w4(4), w4(3) + w4(4)]             ! sum w (x_i - x_i0)/h
      e1 = max(e1, abs(sum(w4) - 1.0_wp))
      e2 = max(e2, maxval(abs(s - ((x - origin)/h - [real(i0, wp), real(j0, wp)]))))
      if (any(w4 < 0.0_wp)) e1 = 1.0_wp
    end do
    call check_close(e1, 0.0_wp, 'bilinear_at: sum = 1, all >= 0', atol=tol)
    call check_close(e2, 0.0_wp, 'bilinear_at: sum w x_i = x', atol=tol)
    call bilinear_at(origin + h*[3.0_wp, 5.0_wp], origin, h, i0, j0, w4)
    call check(i0 == 3 .and. j0 == 5, 'bilinear_at: on node (3,5): lower-left node is (3,5)')
    call check_close(w4, [1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], 'bilinear_at: on node', atol=tol)
    call bilinear_at(origin + h*[3.25_wp, 5.5_wp], origin, h, i0, j0, w4)
    call check_close(w4, [0.375_wp, 0.125_wp, 0.375_wp, 0.125_wp], &
                     'bilinear_at: (3.25, 5.5) closed form', atol=tol)
  end subroutine test_bilinear_at

  ! ---------------------------------------------------------------------------------------------
  ! Linear

  subroutine test_linear()
    real(wp) :: p(8, 4*nrand), r(2), w(4), gw(2, 4), wbig(9), gwbig(2, 9)
    integer :: ip, i0, j0, need
    do ip = 1, nrand
      call random_linear(p(:, ip))
    end do
    call run_set(K_LINEAR, 'linear, random', p(:, 1:nrand), .false.)
    ! On vertical edges, horizontal edges and nodes (exact: binary origin and h).
    do ip = 1, nrand
      call random_number(r)
      p(:, ip) = 0.0_wp
      p(1:2, ip) = origin + h*[real(1 + mod(ip, 6), wp), 1.0_wp + 6.0_wp*r(2)]
      p(:, nrand + ip) = 0.0_wp
      p(1:2, nrand + ip) = origin + h*[1.0_wp + 6.0_wp*r(1), real(1 + mod(ip, 5), wp)]
      p(:, 2*nrand + ip) = 0.0_wp
      p(1:2, 2*nrand + ip) = origin + h*[real(1 + mod(ip, 6), wp), real(1 + mod(ip, 5), wp)]
    end do
    call run_set(K_LINEAR, 'linear, on edges', p(:, 1:2*nrand), .false.)
    call run_set(K_LINEAR, 'linear, on nodes', p(:, 2*nrand + 1:3*nrand), .false.)
    call begin_test('linear, closed form')
    call weights_linear(origin + h*[2.25_wp, 4.5_wp], origin, h, 2, i0, j0, w, gw, need)
    call check(i0 == 2 .and. j0 == 4 .and. need == 2, 'linear: block (2,4), need 2')
    call check_close(w, [0.375_wp, 0.125_wp, 0.375_wp, 0.125_wp], 'linear: weights', atol=tol)
    call check_close(gw(1, :)*h, [-0.5_wp, 0.5_wp, -0.5_wp, 0.5_wp], 'linear: d/dx', atol=tol)
    call check_close(gw(2, :)*h, [-0.75_wp, -0.25_wp, 0.75_wp, 0.25_wp], 'linear: d/dy', &
                     atol=tol)
    call weights_linear(origin + h*[2.25_wp, 4.5_wp], origin, h, 3, i0, j0, wbig, gwbig, need)
    call check(all(wbig([3, 6, 7, 8, 9]) == 0.0_wp) .and. &
               all(gwbig(:, [3, 6, 7, 8, 9]) == 0.0_wp), &
               'linear: nb = 3, the nodes not touched are exactly 0')
    call weights_linear(origin + h*[2.25_wp, 4.5_wp], origin, h, 1, i0, j0, wbig(1:1), &
                      gwbig(:, 1:1), need)
    call check(need == 2, 'linear: nb = 1 reports need = 2')
  end subroutine test_linear

  ! ---------------------------------------------------------------------------------------------
  ! uGIMP

  subroutine test_ugimp()
    real(wp) :: p(8, 2*nrand), r(2), w(9), gw(2, 9), wl(9), gwl(2, 9), e, eg
    real(wp) :: w2(4), gw2(2, 4)
    real(wp), allocatable :: wb(:), gwb(:, :)
    integer :: ip, i0, j0, need, i1, j1, need1
    do ip = 1, nrand
      call random_ugimp(0.05_wp, 0.5_wp, p(:, ip))
    end do
    call run_set(K_UGIMP, 'ugimp, random, half <= h/2', p(:, 1:nrand), .true.)
    call brute_force_ugimp('ugimp vs 200x200 midpoint average', p(:, 1:30))
    call fd_ugimp('ugimp gradient vs central differences', p(:, 1:60))
    do ip = 1, nrand
      call random_ugimp(0.5_wp, 1.6_wp, p(:, ip))
    end do
    call run_set(K_UGIMP, 'ugimp, random, h/2 < half < 1.6h', p(:, 1:nrand), .false.)
    call brute_force_ugimp('ugimp, large, vs 200x200 midpoint', p(:, 1:10))
    call fd_ugimp('ugimp, large, gradient vs central differences', p(:, 1:30))
    ! Edges of the square on grid lines; centres on nodes and edges; square = a cell.
    do ip = 1, nrand
      call random_number(r)
      p(:, ip) = 0.0_wp
      p(3:4, ip) = h*[0.25_wp, 0.125_wp*real(1 + mod(ip, 4), wp)]
      p(1:2, ip) = origin + h*[real(2 + mod(ip, 3), wp) + 0.25_wp, 2.0_wp + 3.0_wp*r(2)]
      p(:, nrand + ip) = 0.0_wp
      p(3:4, nrand + ip) = h*(0.05_wp + 0.45_wp*r)
      p(1:2, nrand + ip) = origin + h*[real(2 + mod(ip, 4), wp), real(2 + mod(ip, 3), wp)]
    end do
    call run_set(K_UGIMP, 'ugimp, square edges on grid lines', p(:, 1:nrand), .true.)
    call run_set(K_UGIMP, 'ugimp, centres on nodes', p(:, nrand + 1:2*nrand), .true.)
    call fd_ugimp('ugimp, square edges on grid lines, gradient vs FD', p(:, 1:30))

    call begin_test('ugimp, square equal to a cell')
    call weights_ugimp(origin + h*[3.5_wp, 2.5_wp], [0.5_wp, 0.5_wp]*h, origin, h, 3, i0, j0, &
                     w, gw, need)
    call check(i0 == 3 .and. j0 == 2 .and. need == 2, 'ugimp cell: block (3,2), need = 2')
    call check_close(w, [0.25_wp, 0.25_wp, 0.0_wp, 0.25_wp, 0.25_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
                     0.0_wp], 'ugimp cell: weights 1/4 on the cell nodes', atol=tol)
    call check_close(gw(1, :)*h, [-0.5_wp, 0.5_wp, 0.0_wp, -0.5_wp, 0.5_wp, 0.0_wp, 0.0_wp, &
                     0.0_wp, 0.0_wp], 'ugimp cell: d/dx = +-1/(2h)', atol=tol)
    ! Centred on a node with half = h/2: 1-D factors 1/8, 3/4, 1/8 (GIMP closed form).
    call weights_ugimp(origin + h*[3.0_wp, 2.0_wp], [0.5_wp, 0.5_wp]*h, origin, h, 3, i0, j0, &
                     w, gw, need)
    call check(i0 == 2 .and. j0 == 1 .and. need == 3, 'ugimp on node: block (2,1), need = 3')
    call check_close(w, [1.0_wp, 6.0_wp, 1.0_wp, 6.0_wp, 36.0_wp, 6.0_wp, 1.0_wp, 6.0_wp, &
                     1.0_wp]/64.0_wp, 'ugimp on node: weights (1,6,1)x(1,6,1)/64', atol=tol)
    call check_close(gw(1, 5), 0.0_wp, 'ugimp on node: centre gradient 0', atol=tol)
    call check_close(gw(1, 4)*h, -0.5_wp*0.75_wp, 'ugimp on node: left gradient', atol=tol)

    call begin_test('ugimp, half = 0 is the linear basis (random, on lines, on nodes)')
    e = 0.0_wp; eg = 0.0_wp
    do ip = 1, nrand
      call random_linear(p(:, ip))
      ! every third particle on a node, every third on a vertical grid line
      if (mod(ip, 3) /= 2) p(1, ip) = origin(1) + h*real(1 + mod(ip, 5), wp)
      if (mod(ip, 3) == 0) p(2, ip) = origin(2) + h*real(1 + mod(ip, 4), wp)
      call weights_ugimp(p(1:2, ip), [0.0_wp, 0.0_wp], origin, h, 3, i0, j0, w, gw, need)
      call weights_linear(p(1:2, ip), origin, h, 3, i1, j1, wl, gwl, need1)
      if (i0 /= i1 .or. j0 /= j1 .or. need /= need1) e = 1.0_wp
      e = max(e, maxval(abs(w - wl)))
      eg = max(eg, h*maxval(abs(gw - gwl)))
    end do
    call check_close(e, 0.0_wp, 'ugimp(half = 0) weights = linear', atol=tol)
    call check_close(eg, 0.0_wp, 'ugimp(half = 0) gradients = linear', atol=tol)

    call begin_test('ugimp, block too small')
    call weights_ugimp(origin + h*[3.3_wp, 3.6_wp], [2.0_wp, 0.3_wp]*h, origin, h, 2, i0, j0, &
                     w2, gw2, need)
    call check(need == 6 .and. i0 == 1 .and. j0 == 3, 'ugimp nb = 2, half = 2h: need = 6')
    allocate(wb(need*need), gwb(2, need*need))
    call weights_ugimp(origin + h*[3.3_wp, 3.6_wp], [2.0_wp, 0.3_wp]*h, origin, h, need, i0, j0, &
                     wb, gwb, need1)
    e = 0.0_wp
    call add_props_scalar(wb, gwb, i0, j0, need, origin + h*[3.3_wp, 3.6_wp], e)
    call check_close(e, 0.0_wp, 'ugimp called again with nb = need: properties hold', atol=tol)
  end subroutine test_ugimp

  subroutine add_props_scalar(w, gw, i0, j0, nb, xref, e)
    real(wp), intent(in) :: w(:), gw(:, :), xref(2)
    integer, intent(in) :: i0, j0, nb
    real(wp), intent(out) :: e
    real(wp) :: err(4)
    err = 0.0_wp
    call add_props(w, gw, i0, j0, nb, xref, err)
    e = maxval(err)
  end subroutine add_props_scalar

  ! Hat of node (i, j) at x (independent of the module).
  real(wp) function hat2(x, i, j)
    real(wp), intent(in) :: x(2)
    integer, intent(in) :: i, j
    real(wp) :: u(2)
    u = (x - origin)/h - [real(i, wp), real(j, wp)]
    hat2 = max(0.0_wp, 1.0_wp - abs(u(1)))*max(0.0_wp, 1.0_wp - abs(u(2)))
  end function hat2

  ! uGIMP weights against the midpoint-rule average of N_i over the square (200 x 200); the
  ! sum of those averages over the block must be 1 (no touched node left out of the block).
  subroutine brute_force_ugimp(label, ps)
    character(len=*), intent(in) :: label
    real(wp), intent(in) :: ps(:, :)
    integer, parameter :: ns = 200
    real(wp) :: w(nbig*nbig), gw(2, nbig*nbig), avg(nbig*nbig), x(2), e, es
    integer :: ip, i0, j0, need, m1, m2, a, b
    e = 0.0_wp; es = 0.0_wp
    do ip = 1, size(ps, 2)
      call weights_ugimp(ps(1:2, ip), ps(3:4, ip), origin, h, nbig, i0, j0, w, gw, need)
      avg = 0.0_wp
      do m2 = 1, ns
        do m1 = 1, ns
          x = ps(1:2, ip) - ps(3:4, ip) + 2.0_wp*ps(3:4, ip)* &
              ([real(m1, wp), real(m2, wp)] - 0.5_wp)/real(ns, wp)
          do b = 0, nbig - 1
            do a = 0, nbig - 1
              avg(1 + a + nbig*b) = avg(1 + a + nbig*b) + hat2(x, i0 + a, j0 + b)
            end do
          end do
        end do
      end do
      avg = avg/real(ns*ns, wp)
      e = max(e, maxval(abs(w - avg)))
      es = max(es, abs(sum(avg) - 1.0_wp))
    end do
    call begin_test(label)
    call check_close(e, 0.0_wp, label//': weights', atol=1.0e-4_wp)
    call check_close(es, 0.0_wp, label//': block holds all the mass', atol=1.0e-12_wp)
  end subroutine brute_force_ugimp

  ! uGIMP gradients against central differences of the weights (step 1e-7 h), by global node.
  subroutine fd_ugimp(label, ps)
    character(len=*), intent(in) :: label
    real(wp), intent(in) :: ps(:, :)
    real(wp), parameter :: step = 1.0e-7_wp
    real(wp) :: w(nbig*nbig), gw(2, nbig*nbig), wp_(nbig*nbig), wm(nbig*nbig), gdum(2, nbig*nbig)
    real(wp) :: e, dx(2), fd, g
    integer :: ip, i0, j0, need, ip0, jp0, im0, jm0, d, i, j, ndum
    e = 0.0_wp
    do ip = 1, size(ps, 2)
      call weights_ugimp(ps(1:2, ip), ps(3:4, ip), origin, h, nbig, i0, j0, w, gw, need)
      do d = 1, 2
        dx = 0.0_wp
        dx(d) = step*h
        call weights_ugimp(ps(1:2, ip) + dx, ps(3:4, ip), origin, h, nbig, ip0, jp0, wp_, &
                         gdum, ndum)
        call weights_ugimp(ps(1:2, ip) - dx, ps(3:4, ip), origin, h, nbig, im0, jm0, wm, &
                         gdum, ndum)
        do j = j0 - 1, j0 + nbig
          do i = i0 - 1, i0 + nbig
            fd = (weight_at(i, j, ip0, jp0, nbig, wp_) - weight_at(i, j, im0, jm0, nbig, wm)) &
                 /(2.0_wp*step)
            g = 0.0_wp
            if (i >= i0 .and. i < i0 + nbig .and. j >= j0 .and. j < j0 + nbig) &
              g = gw(d, 1 + (i - i0) + nbig*(j - j0))*h
            e = max(e, abs(fd - g))
          end do
        end do
      end do
    end do
    call begin_test(label)
    call check_close(e, 0.0_wp, label, atol=1.0e-6_wp)
  end subroutine fd_ugimp

  ! ---------------------------------------------------------------------------------------------
  ! CPDI1

  subroutine test_cpdi1()
    real(wp) :: p(8, 2*nrand), q(8), w(nbig*nbig), gw(2, nbig*nbig), w2(nbig*nbig)
    real(wp) :: gw2(2, nbig*nbig), r(2), e, eg, ev, area, cen(2), jmin, vol
    real(wp) :: ws(4), gws(2, 4)
    real(wp), allocatable :: wb(:), gwb(:, :)
    integer :: ip, i0, j0, need, i1, j1, need1, nbad
    do ip = 1, nrand
      call random_parallelogram(0.05_wp, 0.25_wp, p(:, ip))
    end do
    call run_set(K_CPDI1, 'cpdi1, random sheared parallelograms, |r| <= h/4', p(:, 1:nrand), &
                 .true.)
    do ip = 1, nrand
      call random_parallelogram(0.05_wp, 1.2_wp, p(:, ip))
    end do
    call run_set(K_CPDI1, 'cpdi1, random stretched parallelograms, |r| <= 1.2h', &
                 p(:, 1:nrand), .false.)
    ! Corners on grid lines and on nodes.
    do ip = 1, nrand
      call random_number(r)
      p(:, ip) = 0.0_wp
      ! Axis-aligned (corners at +0, +0.5 / +0, +0.5 or +0.25, +0.75) or sheared (r2x = h/8,
      ! corners at x = +0, +0.25, +0.5, +0.75), centre height random or on a grid line + h/4.
      p(1:2, ip) = origin + h*[real(2 + mod(ip, 3), wp) + 0.25_wp, real(2 + mod(ip, 3), wp)]
      p(3:6, ip) = h*[0.25_wp, 0.0_wp, 0.0_wp, 0.25_wp]
      if (mod(ip, 2) == 0) p(2, ip) = p(2, ip) + 0.25_wp*h
      if (mod(ip, 3) == 0) p(2, ip) = origin(2) + h*(2.0_wp + 3.0_wp*r(2))
      if (mod(ip, 4) >= 2) then
        p(1, ip) = p(1, ip) + 0.125_wp*h
        p(5, ip) = 0.125_wp*h
      end if
      p(:, nrand + ip) = 0.0_wp
      p(1:2, nrand + ip) = origin + h*[real(2 + mod(ip, 4), wp), real(2 + mod(ip, 3), wp)] &
                           + h*[0.5_wp, 0.5_wp]
      p(3:6, nrand + ip) = h*[0.5_wp, 0.0_wp, 0.0_wp, 0.5_wp]
    end do
    call run_set(K_CPDI1, 'cpdi1, corners on grid lines', p(:, 1:nrand), .true.)
    call run_set(K_CPDI1, 'cpdi1, corners on nodes (domain = cell)', p(:, nrand + 1:2*nrand), &
                 .false.)

    call begin_test('cpdi1, domain equal to a cell')
    call weights_cpdi1(origin + h*[3.5_wp, 2.5_wp], [0.5_wp, 0.0_wp]*h, [0.0_wp, 0.5_wp]*h, &
                     origin, h, 2, i0, j0, ws, gws, need)
    call check(i0 == 3 .and. j0 == 2 .and. need == 2, 'cpdi1 cell: block (3,2), need = 2')
    call check_close(ws, [0.25_wp, 0.25_wp, 0.25_wp, 0.25_wp], 'cpdi1 cell: weights 1/4', &
                     atol=tol)
    call check_close([gws(1, :), gws(2, :)]*h, 0.5_wp*[-1.0_wp, 1.0_wp, -1.0_wp, 1.0_wp, &
                     -1.0_wp, -1.0_wp, 1.0_wp, 1.0_wp], 'cpdi1 cell: gradients +-1/(2h)', atol=tol)

    ! V = 4|r1 x r2| is the area of the corners; CPDI1 equals CPDI2 on parallelograms (the
    ! bilinear map is affine, each corner weighs 1/4); swapped r1, r2 (clockwise corners) give
    ! the same gradients because the formula uses the signed volume.
    call begin_test('cpdi1 vs cpdi2 on parallelograms')
    e = 0.0_wp; eg = 0.0_wp; ev = 0.0_wp; nbad = 0
    do ip = 1, nrand
      call random_parallelogram(0.05_wp, 1.0_wp, q)
      call cpdi2_geometry(corners_of(q), area, cen, jmin)
      vol = 4.0_wp*abs(q(3)*q(6) - q(4)*q(5))
      ev = max(ev, abs(area - vol)/vol, abs(jmin - 1.0_wp))
      call weights_cpdi1(q(1:2), q(3:4), q(5:6), origin, h, nbig, i0, j0, w, gw, need)
      call weights_cpdi2(corners_of(q), origin, h, nbig, i1, j1, w2, gw2, need1)
      if (i0 /= i1 .or. j0 /= j1 .or. need /= need1) nbad = nbad + 1
      e = max(e, maxval(abs(w - w2)))
      eg = max(eg, h*maxval(abs(gw - gw2)))
      call weights_cpdi1(q(1:2), q(5:6), q(3:4), origin, h, nbig, i1, j1, w2, gw2, need1)
      eg = max(eg, h*maxval(abs(gw - gw2)))
      e = max(e, maxval(abs(w - w2)))
    end do
    call check_close(ev, 0.0_wp, 'cpdi1: 4|r1 x r2| = area of the corners, jmin = 1', atol=tol)
    call check(nbad == 0, 'cpdi1 and cpdi2: same block and need')
    call check_close(e, 0.0_wp, 'cpdi1 weights = cpdi2 weights; r1, r2 swapped', atol=tol)
    call check_close(eg, 0.0_wp, 'cpdi1 gradients = cpdi2 gradients; r1, r2 swapped', atol=tol)

    call begin_test('cpdi1, rectangle inside one cell = uGIMP (exact average)')
    e = 0.0_wp
    do ip = 1, nrand
      call random_number(r)
      q = 0.0_wp
      q(3:6) = h*[0.02_wp + 0.2_wp*r(1), 0.0_wp, 0.0_wp, 0.02_wp + 0.2_wp*r(2)]
      call random_number(r)
      q(1:2) = origin + h*([3.0_wp, 4.0_wp] + [q(3), q(6)]/h &
               + r*(1.0_wp - 2.0_wp*[q(3), q(6)]/h))
      call weights_cpdi1(q(1:2), q(3:4), q(5:6), origin, h, nbig, i0, j0, w, gw, need)
      call weights_ugimp(q(1:2), [q(3), q(6)], origin, h, nbig, i1, j1, w2, gw2, need1)
      if (i0 /= i1 .or. j0 /= j1 .or. need /= need1) e = 1.0_wp
      e = max(e, maxval(abs(w - w2)), h*maxval(abs(gw - gw2)))
    end do
    call check_close(e, 0.0_wp, 'cpdi1 = ugimp for rectangles inside a cell', atol=tol)

    call begin_test('cpdi1, block too small')
    q(1:6) = [origin + h*[4.1_wp, 3.7_wp], 1.5_wp*h, 0.3_wp*h, -0.2_wp*h, 0.9_wp*h]
    call weights_cpdi1(q(1:2), q(3:4), q(5:6), origin, h, 2, i0, j0, ws, gws, need)
    call check(need > 2, 'cpdi1 nb = 2 with a domain of 3.4h: need > 2 (no out-of-bounds)')
    allocate(wb(need*need), gwb(2, need*need))
    call weights_cpdi1(q(1:2), q(3:4), q(5:6), origin, h, need, i0, j0, wb, gwb, need1)
    call add_props_scalar(wb, gwb, i0, j0, need, q(1:2), e)
    call check(need1 == need .and. need == 5, 'cpdi1 domain of 3.4h x 2.4h: need = 5')
    call check_close(e, 0.0_wp, 'cpdi1 called again with nb = need: properties hold', atol=tol)

    call begin_test('cpdi1, zero volume')
    call weights_cpdi1(origin + h*[4.1_wp, 3.7_wp], [0.3_wp, 0.1_wp]*h, [0.6_wp, 0.2_wp]*h, &
                     origin, h, nbig, i0, j0, w, gw, need)
    call check(all(ieee_is_nan(w)) .and. all(ieee_is_nan(gw)), &
               'cpdi1: r1 parallel to r2 gives NaN, not silent zeros')
  end subroutine test_cpdi1

  ! ---------------------------------------------------------------------------------------------
  ! CPDI2

  subroutine test_cpdi2()
    real(wp) :: p(8, 2*nrand), r(2), ws(4), gws(2, 4), w(nbig*nbig), gw(2, nbig*nbig)
    real(wp) :: w2(nbig*nbig), gw2(2, nbig*nbig), xc(2, 4), e, q(8)
    real(wp), allocatable :: wb(:), gwb(:, :)
    integer :: ip, i0, j0, need, i1, j1, need1
    do ip = 1, nrand
      call random_convex_quad(0.1_wp, 0.45_wp, p(:, ip))
    end do
    call run_set(K_CPDI2, 'cpdi2, random convex quads below a cell', p(:, 1:nrand), .true.)
    call gauss_set('cpdi2 vs 4x4 Gauss, quads below a cell', p(:, 1:nrand))
    do ip = 1, nrand
      call random_convex_quad(0.1_wp, 1.6_wp, p(:, ip))
    end do
    call run_set(K_CPDI2, 'cpdi2, random distorted convex quads up to 3h', p(:, 1:nrand), &
                 .false.)
    call gauss_set('cpdi2 vs 4x4 Gauss, quads up to 3h', p(:, 1:nrand))
    ! Corners on grid lines; corners on nodes.
    do ip = 1, nrand
      call random_number(r)
      xc(:, 1) = origin + h*[3.0_wp, 2.0_wp + r(1)]
      xc(:, 2) = origin + h*[3.5_wp + 0.5_wp*r(2), 2.0_wp]
      xc(:, 3) = origin + h*[4.0_wp, 3.0_wp + 0.5_wp*r(1)]
      xc(:, 4) = origin + h*[3.0_wp + r(2), 4.0_wp]
      p(:, ip) = reshape(xc, [8])
      xc(:, 1) = origin + h*[real(2 + mod(ip, 3), wp), real(2 + mod(ip, 2), wp)]
      xc(:, 2) = xc(:, 1) + h*[real(1 + mod(ip, 2), wp), 0.0_wp]
      xc(:, 3) = xc(:, 1) + h*[real(1 + mod(ip, 3), wp), 1.0_wp]
      xc(:, 4) = xc(:, 1) + h*[0.0_wp, 1.0_wp]
      p(:, nrand + ip) = reshape(xc, [8])
    end do
    call run_set(K_CPDI2, 'cpdi2, corners on grid lines', p(:, 1:nrand), .false.)
    call gauss_set('cpdi2 vs Gauss, corners on grid lines', p(:, 1:nrand))
    call run_set(K_CPDI2, 'cpdi2, corners on nodes', p(:, nrand + 1:2*nrand), .false.)
    call gauss_set('cpdi2 vs Gauss, corners on nodes', p(:, nrand + 1:2*nrand))

    ! A domain equal to cell (3,2): every corner is a node, N_i(x_c) = delta, so each cell node
    ! gets its corner weight (1/V) int M_c dA = 1/4 and the gradient
    ! (1/(2V)) (y_next - y_prev, x_prev - x_next) = (-+1/(2h), -+1/(2h)), which is also the
    ! average of grad N_i over the cell. Nothing else is touched, so need = 2.
    call begin_test('cpdi2, domain equal to a cell')
    xc = reshape([3.0_wp, 2.0_wp, 4.0_wp, 2.0_wp, 4.0_wp, 3.0_wp, 3.0_wp, 3.0_wp], [2, 4])
    do ip = 1, 4
      xc(:, ip) = origin + h*xc(:, ip)
    end do
    call weights_cpdi2(xc, origin, h, 2, i0, j0, ws, gws, need)
    call check(i0 == 3 .and. j0 == 2 .and. need == 2, 'cpdi2 cell: block (3,2), need = 2')
    call check_close(ws, [0.25_wp, 0.25_wp, 0.25_wp, 0.25_wp], 'cpdi2 cell: weights 1/4', &
                     atol=tol)
    call check_close([gws(1, :), gws(2, :)]*h, 0.5_wp*[-1.0_wp, 1.0_wp, -1.0_wp, 1.0_wp, &
                     -1.0_wp, -1.0_wp, 1.0_wp, 1.0_wp], 'cpdi2 cell: gradients +-1/(2h)', atol=tol)

    ! A trapezoid inside one cell has N_i(x(s,t)) of degree 2 in s and t, which the corner
    ! interpolant does not reproduce: CPDI2 weights differ from the exact averages of N_i
    ! (here computed by 8x8 Gauss, exact for that integrand). An axis-aligned rectangle is
    ! reproduced exactly (= uGIMP).
    call begin_test('cpdi2 vs exact average of N_i')
    xc = reshape([3.1_wp, 2.1_wp, 3.9_wp, 2.1_wp, 3.6_wp, 2.8_wp, 3.3_wp, 2.8_wp], [2, 4])
    do ip = 1, 4
      xc(:, ip) = origin + h*xc(:, ip)
    end do
    call weights_cpdi2(xc, origin, h, nbig, i0, j0, w, gw, need)
    call exact_average(xc, i0, j0, w2)
    e = maxval(abs(w - w2))
    call check(e > 1.0e-4_wp, 'cpdi2 trapezoid in a cell: not the exact average of N_i')
    call check_close(sum(w2), 1.0_wp, 'exact average of N_i sums to 1', atol=tol)
    e = 0.0_wp
    do ip = 1, 50
      call random_number(r)
      q(1:2) = origin + h*([3.05_wp, 2.05_wp] + 0.4_wp*r)
      call random_number(r)
      q(3:4) = q(1:2) + h*(0.1_wp + 0.4_wp*r)
      xc = reshape([q(1), q(2), q(3), q(2), q(3), q(4), q(1), q(4)], [2, 4])
      call weights_cpdi2(xc, origin, h, nbig, i0, j0, w, gw, need)
      call exact_average(xc, i0, j0, w2)
      e = max(e, maxval(abs(w - w2)))
      call weights_ugimp(0.5_wp*(q(1:2) + q(3:4)), 0.5_wp*(q(3:4) - q(1:2)), origin, h, nbig, &
                       i1, j1, w2, gw2, need1)
      if (i0 /= i1 .or. j0 /= j1 .or. need /= need1) e = 1.0_wp
      e = max(e, maxval(abs(w - w2)), h*maxval(abs(gw - gw2)))
    end do
    call check_close(e, 0.0_wp, 'cpdi2 = exact average = ugimp, rectangles in a cell', atol=tol)

    call begin_test('cpdi2, block too small')
    xc = reshape([1.2_wp, 1.1_wp, 4.9_wp, 1.4_wp, 4.2_wp, 3.3_wp, 1.5_wp, 2.9_wp], [2, 4])
    do ip = 1, 4
      xc(:, ip) = origin + h*xc(:, ip)
    end do
    call weights_cpdi2(xc, origin, h, 2, i0, j0, ws, gws, need)
    call check(need == 5 .and. i0 == 1 .and. j0 == 1, 'cpdi2 nb = 2, domain 3.7h wide: need 5')
    allocate(wb(need*need), gwb(2, need*need))
    call weights_cpdi2(xc, origin, h, need, i0, j0, wb, gwb, need1)
    call add_props_scalar(wb, gwb, i0, j0, need, centroid_of(xc), e)
    call check_close(e, 0.0_wp, 'cpdi2 called again with nb = need: properties hold', atol=tol)

    call begin_test('cpdi2, zero area (symmetric bow-tie)')
    xc = reshape([3.2_wp, 2.2_wp, 3.8_wp, 2.8_wp, 3.8_wp, 2.2_wp, 3.2_wp, 2.8_wp], [2, 4])
    do ip = 1, 4
      xc(:, ip) = origin + h*xc(:, ip)
    end do
    call weights_cpdi2(xc, origin, h, nbig, i0, j0, w, gw, need)
    call check(all(ieee_is_nan(w)) .and. all(ieee_is_nan(gw)), &
               'cpdi2: zero area gives NaN, not silent zeros')
  end subroutine test_cpdi2

  ! Gauss-Legendre points and weights on [-1, 1]: Newton's method on P_n (recurrence).
  subroutine gauss_rule(n, xg, wg)
    integer, intent(in) :: n
    real(wp), intent(out) :: xg(n), wg(n)
    real(wp) :: x, p0, p1, p2, dp, dx
    integer :: i, it, l
    do i = 1, n
      x = -cos(pi*(real(i, wp) - 0.25_wp)/(real(n, wp) + 0.5_wp))
      do it = 1, 100
        p0 = 1.0_wp
        p1 = x
        do l = 2, n
          p2 = (real(2*l - 1, wp)*x*p1 - real(l - 1, wp)*p0)/real(l, wp)
          p0 = p1
          p1 = p2
        end do
        dp = real(n, wp)*(x*p1 - p0)/(x*x - 1.0_wp)
        dx = p1/dp
        x = x - dx
        if (abs(dx) <= 1.0e-16_wp) exit
      end do
      xg(i) = x
      wg(i) = 2.0_wp/((1.0_wp - x*x)*dp*dp)
    end do
  end subroutine gauss_rule

  ! Bilinear map of the quad from [-1,1]^2 at (xi, eta): shape functions, derivatives, x, J.
  subroutine iso_map(xc, xi, eta, m, dm, x, jac)
    real(wp), intent(in) :: xc(2, 4), xi, eta
    real(wp), intent(out) :: m(4), dm(2, 4), x(2), jac(2, 2)
    real(wp), parameter :: sx(4) = [-1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp]
    real(wp), parameter :: sy(4) = [-1.0_wp, -1.0_wp, 1.0_wp, 1.0_wp]
    integer :: c
    x = 0.0_wp; jac = 0.0_wp
    do c = 1, 4
      m(c) = 0.25_wp*(1.0_wp + sx(c)*xi)*(1.0_wp + sy(c)*eta)
      dm(1, c) = 0.25_wp*sx(c)*(1.0_wp + sy(c)*eta)
      dm(2, c) = 0.25_wp*sy(c)*(1.0_wp + sx(c)*xi)
      x = x + m(c)*xc(:, c)
      jac(:, 1) = jac(:, 1) + dm(1, c)*xc(:, c)     ! dx/dxi
      jac(:, 2) = jac(:, 2) + dm(2, c)*xc(:, c)     ! dx/deta
    end do
  end subroutine iso_map

  ! CPDI2 against 4x4 Gauss integration over the quad of the isoparametric interpolant
  ! Ntilde_i = sum_c N_i(x_c) M_c: w_i = (1/A) int Ntilde_i dA and, for the gradient,
  ! gw_i = (1/A) int grad Ntilde_i dA with grad = J^-T grad_xi (identity to be checked).
  subroutine gauss_set(label, ps)
    character(len=*), intent(in) :: label
    real(wp), intent(in) :: ps(:, :)
    real(wp) :: xc(2, 4), w(nbig*nbig), gw(2, nbig*nbig), xg(4), wg(4), m(4), dm(2, 4)
    real(wp) :: x(2), jac(2, 2), detj, jinv(2, 2), nc(4), gi(2), wi, gint(2), area, ew, eg
    integer :: ip, i0, j0, need, a, b, c, g1, g2
    call gauss_rule(4, xg, wg)
    ew = 0.0_wp; eg = 0.0_wp
    do ip = 1, size(ps, 2)
      xc = reshape(ps(:, ip), [2, 4])
      call weights_cpdi2(xc, origin, h, nbig, i0, j0, w, gw, need)
      do b = -1, nbig
        do a = -1, nbig
          do c = 1, 4
            nc(c) = hat2(xc(:, c), i0 + a, j0 + b)
          end do
          wi = 0.0_wp; gint = 0.0_wp; area = 0.0_wp
          do g2 = 1, 4
            do g1 = 1, 4
              call iso_map(xc, xg(g1), xg(g2), m, dm, x, jac)
              detj = jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1)
              jinv = reshape([jac(2, 2), -jac(2, 1), -jac(1, 2), jac(1, 1)], [2, 2])/detj
              gi = matmul(transpose(jinv), matmul(dm, nc))     ! grad Ntilde_i at the point
              wi = wi + wg(g1)*wg(g2)*detj*dot_product(m, nc)
              gint = gint + wg(g1)*wg(g2)*detj*gi
              area = area + wg(g1)*wg(g2)*detj
            end do
          end do
          ew = max(ew, abs(wi/area - weight_at(i0 + a, j0 + b, i0, j0, nbig, w)))
          if (a >= 0 .and. a < nbig .and. b >= 0 .and. b < nbig) then
            eg = max(eg, h*maxval(abs(gint/area - gw(:, 1 + a + nbig*b))))
          else
            eg = max(eg, h*maxval(abs(gint/area)))
          end if
        end do
      end do
    end do
    call begin_test(label)
    call check_close(ew, 0.0_wp, label//': weights', atol=tol)
    call check_close(eg, 0.0_wp, label//': gradients = average of grad Ntilde_i', atol=tol)
  end subroutine gauss_set

  ! Exact average over the quad of the grid N_i of the nodes (i0..i0+nbig-1, j0..): 8x8 Gauss
  ! (exact when the quad lies in one cell: N_i(x(xi, eta)) det J has degree <= 3 per variable).
  subroutine exact_average(xc, i0, j0, wex)
    real(wp), intent(in) :: xc(2, 4)
    integer, intent(in) :: i0, j0
    real(wp), intent(out) :: wex(nbig*nbig)
    real(wp) :: xg(8), wg(8), m(4), dm(2, 4), x(2), jac(2, 2), detj, area
    integer :: a, b, g1, g2
    call gauss_rule(8, xg, wg)
    wex = 0.0_wp; area = 0.0_wp
    do g2 = 1, 8
      do g1 = 1, 8
        call iso_map(xc, xg(g1), xg(g2), m, dm, x, jac)
        detj = jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1)
        area = area + wg(g1)*wg(g2)*detj
        do b = 0, nbig - 1
          do a = 0, nbig - 1
            wex(1 + a + nbig*b) = wex(1 + a + nbig*b) + wg(g1)*wg(g2)*detj*hat2(x, i0 + a, j0 + b)
          end do
        end do
      end do
    end do
    wex = wex/area
  end subroutine exact_average

  ! ---------------------------------------------------------------------------------------------
  ! cpdi2_geometry against independent polygon formulas

  ! Shoelace area and polygon centroid, relative to the corner mean.
  subroutine polygon_area_centroid(xc, area, cen)
    real(wp), intent(in) :: xc(2, 4)
    real(wp), intent(out) :: area, cen(2)
    real(wp) :: ref(2), y(2, 4), cr
    integer :: c, c2
    ref = 0.25_wp*sum(xc, dim=2)
    do c = 1, 4
      y(:, c) = xc(:, c) - ref
    end do
    area = 0.0_wp; cen = 0.0_wp
    do c = 1, 4
      c2 = mod(c, 4) + 1
      cr = y(1, c)*y(2, c2) - y(1, c2)*y(2, c)
      area = area + 0.5_wp*cr
      cen = cen + (y(:, c) + y(:, c2))*cr
    end do
    cen = ref + cen/(6.0_wp*area)
  end subroutine polygon_area_centroid

  function centroid_of(xc) result(cen)
    real(wp), intent(in) :: xc(2, 4)
    real(wp) :: cen(2), area
    call polygon_area_centroid(xc, area, cen)
  end function centroid_of

  subroutine test_geometry()
    real(wp) :: p(8), xc(2, 4), area, cen(2), jmin, a2, c2(2), ea, ec, ej
    integer :: ip, nbad
    call begin_test('cpdi2_geometry')
    ea = 0.0_wp; ec = 0.0_wp; nbad = 0
    do ip = 1, nrand
      call random_convex_quad(0.1_wp, 1.6_wp, p)
      xc = reshape(p, [2, 4])
      call cpdi2_geometry(xc, area, cen, jmin)
      call polygon_area_centroid(xc, a2, c2)
      ea = max(ea, abs(area - a2)/a2)
      ec = max(ec, maxval(abs(cen - c2))/h)
      if (.not. (jmin > 0.0_wp .and. area > 0.0_wp)) nbad = nbad + 1
    end do
    call check_close(ea, 0.0_wp, 'area = shoelace (random convex quads)', atol=tol)
    call check_close(ec, 0.0_wp, 'centroid = polygon centroid (random convex quads)', atol=tol)
    call check(nbad == 0, 'convex counter-clockwise quads: area > 0, jmin > 0')
    ej = 0.0_wp
    do ip = 1, nrand
      call random_parallelogram(0.05_wp, 1.0_wp, p)
      call cpdi2_geometry(corners_of(p), area, cen, jmin)
      ej = max(ej, abs(jmin - 1.0_wp), maxval(abs(cen - p(1:2)))/h)
    end do
    call check_close(ej, 0.0_wp, 'parallelograms: jmin = 1, centroid = centre', atol=tol)
    ! Trapezoid (0,0), (2,0), (1.5,1), (0.5,1): area 1.5, corner Jacobians 2, 2, 1, 1 on the
    ! unit square, so jmin = 1/1.5; centroid (1, (b1 + 2 b2)/(3 (b1 + b2))) = (1, 4/9).
    xc = reshape([0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 1.5_wp, 1.0_wp, 0.5_wp, 1.0_wp], [2, 4])
    call cpdi2_geometry(xc, area, cen, jmin)
    call check_close([area, cen, jmin], [1.5_wp, 1.0_wp, 4.0_wp/9.0_wp, 2.0_wp/3.0_wp], &
                     'trapezoid: area, centroid, jmin by hand', atol=tol)
    ! Symmetric bow-tie (zero area) and an asymmetric one.
    xc = reshape([0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 4])
    call cpdi2_geometry(xc, area, cen, jmin)
    call check(abs(area) <= tol .and. jmin <= 0.0_wp, 'symmetric bow-tie: area 0, jmin <= 0')
    xc = reshape([0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.2_wp, 1.0_wp, 1.0_wp, 1.3_wp], [2, 4])
    call cpdi2_geometry(xc, area, cen, jmin)
    call check(jmin <= 0.0_wp, 'asymmetric bow-tie: jmin <= 0')
    ! Non-convex dart (corner 3 is reflex): area > 0 but jmin <= 0.
    xc = reshape([0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 0.5_wp, 0.5_wp, 0.0_wp, 2.0_wp], [2, 4])
    call cpdi2_geometry(xc, area, cen, jmin)
    call polygon_area_centroid(xc, a2, c2)
    call check(area > 0.0_wp .and. jmin <= 0.0_wp, 'dart: area > 0, jmin <= 0')
    call check_close([area, cen], [a2, c2], 'dart: area and centroid = polygon formulas', &
                     atol=tol)
    ! Clockwise (inverted) unit square.
    xc = reshape([0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, 0.0_wp], [2, 4])
    call cpdi2_geometry(xc, area, cen, jmin)
    call check(area < 0.0_wp .and. jmin <= 0.0_wp, 'clockwise square: area < 0, jmin <= 0')
    call check_close(area, -1.0_wp, 'clockwise square: area = -1', atol=tol)
  end subroutine test_geometry

  ! The lean folding check (the driver's, before it keeps a good state) against
  ! cpdi2_geometry's jmin: .not. jmin > 0, the same decision for every quad, also for NaN,
  ! infinite, overflowing and underflowing corners (the traps are off for this test only).
  subroutine test_folded()
    type(ieee_flag_type), parameter :: traps(3) = [ieee_invalid, ieee_overflow, &
                                                   ieee_divide_by_zero]
    integer, parameter :: nq = 20000, nmesh = 40
    logical :: halting(3), same
    real(wp) :: xc(2, 4), area, cen(2), jmin, r(11), special(8), scale, mesh(2, 4*nmesh)
    integer :: ip, m, nfold, ndiff, corner(4, nmesh), first
    call begin_test('cpdi2_folded')
    call ieee_get_halting_mode(traps, halting)
    call ieee_set_halting_mode(traps, .false.)
    special = [ieee_value(0.0_wp, ieee_quiet_nan), ieee_value(0.0_wp, ieee_positive_inf), &
               ieee_value(0.0_wp, ieee_negative_inf), huge(0.0_wp), -huge(0.0_wp), &
               0.9_wp*huge(0.0_wp), 5.0e-324_wp, 0.0_wp]
    nfold = 0
    ndiff = 0
    do ip = 1, nq
      call random_number(r)
      select case (mod(ip, 4))
      case (0)                               ! convex, counter-clockwise
        call random_convex_quad(0.1_wp, 1.6_wp, r(1:8))
      case (1)                               ! parallelograms, either orientation
        call random_parallelogram(0.05_wp, 1.0_wp, r(1:8))
        r(1:8) = reshape(corners_of(r(1:8)), [8])
        if (r(9) < 0.5_wp) r(1:8) = [r(1:2), r(7:8), r(5:6), r(3:4)]
      case default                           ! anything: folded, bow-ties, degenerate
        r(1:8) = 2.0_wp*r(1:8) - 1.0_wp
        if (r(9) < 0.3_wp) r(5:6) = r(3:4) + 1.0e-17_wp*r(7:8)
      end select
      scale = 10.0_wp**nint(-160.0_wp + 310.0_wp*r(10))
      if (r(11) < 0.5_wp) scale = 1.0_wp
      xc = reshape(r(1:8), [2, 4])*scale
      if (mod(ip, 7) == 0) then              ! one or two special coordinates
        call random_number(r)
        xc(1 + int(2.0_wp*r(1)), 1 + int(4.0_wp*r(2))) = special(1 + int(8.0_wp*r(3)))
        if (r(4) < 0.5_wp) xc(1 + int(2.0_wp*r(5)), 1 + int(4.0_wp*r(6))) = &
          special(1 + int(8.0_wp*r(7)))
      end if
      call cpdi2_geometry(xc, area, cen, jmin)
      if (.not. jmin > 0.0_wp) nfold = nfold + 1
      if (cpdi2_folded(xc) .neqv. .not. jmin > 0.0_wp) ndiff = ndiff + 1
    end do
    call check(ndiff == 0, 'cpdi2_folded = .not. jmin > 0 of cpdi2_geometry on '// &
               'random, degenerate, scaled and non-finite quads')
    call check(nfold > nq/4 .and. nfold < 3*nq/4, 'the random quads hold folded and '// &
               'unfolded ones')
    ! A corner Jacobian of the smallest subnormal over an area of 100: jmin underflows to 0.
    xc = reshape([0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 2.0_wp, 5.0e-324_wp, 0.0_wp, 100.0_wp], &
                 [2, 4])
    call cpdi2_geometry(xc, area, cen, jmin)
    call check(cpdi2_folded(xc) .and. .not. jmin > 0.0_wp, 'underflowing jmin: folded')
    ! The first folded particle of a mesh of separate quads.
    do ip = 1, nmesh
      call random_convex_quad(0.1_wp, 1.6_wp, r(1:8))
      mesh(:, 4*ip - 3:4*ip) = reshape(r(1:8), [2, 4])
      corner(:, ip) = 4*(ip - 1) + [1, 2, 3, 4]
    end do
    call check(cpdi2_first_folded(nmesh, 4*nmesh, corner, mesh) == 0, 'no folded particle: 0')
    same = .true.
    do m = 1, 3
      call random_number(r)
      ip = 1 + int(real(nmesh, wp)*r(1))
      corner(:, ip) = corner([1, 4, 3, 2], ip)  ! clockwise: inverted
      first = 0
      do nfold = nmesh, 1, -1
        call cpdi2_geometry(mesh(:, corner(:, nfold)), area, cen, jmin)
        if (.not. jmin > 0.0_wp) first = nfold
      end do
      same = same .and. first > 0 .and. cpdi2_first_folded(nmesh, 4*nmesh, corner, mesh) == first
    end do
    call check(same, 'cpdi2_first_folded: the first particle that cpdi2_geometry finds folded')
    call ieee_set_flag([traps, ieee_underflow], .false.)
    call ieee_set_halting_mode(traps, halting)
  end subroutine test_folded
end program test_basis
