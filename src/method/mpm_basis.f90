!> Particle basis functions on a uniform grid of bilinear hats: classic MPM (linear), uGIMP,
!> CPDI1 (parallelogram domains) and CPDI2 / CPDI-Q4 (quadrilateral domains).
! SPDX-License-Identifier: MIT
!
! Conventions (docs/method.md has the formulas and references):
! - Square cells of side h; node (i, j) sits at origin + h*(i, j). N_i is the tensor product of
!   1-D hats of half-width h.
! - A particle's support is an nb x nb block of nodes with lower-left node (i0, j0); local index
!   k = 1 + a + nb*b is node (i0 + a, j0 + b), a, b = 0..nb-1. Nodes of the block that the
!   particle does not touch get exactly zero weight and gradient.
! - The block is the tightest one: i0 = floor((xmin - origin_x)/h) with xmin the leftmost point
!   of the support; `need` is the number of node columns/rows touched (max over the two
!   directions, never below 2). When need > nb, w and gw are returned as zeros and are not valid:
!   the caller enlarges nb and calls again. Grid bounds are the caller's job.
! - Internally every position is scaled by 1/h, so that node i sits at the integer i.
! - A CPDI domain of zero area gives NaN weights and gradients (never silently zero); callers
!   check cpdi2_geometry first.
module mpm_basis
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use mpm_kinds, only: wp
  implicit none
  private
  public :: weights_linear, weights_ugimp, weights_cpdi1, weights_cpdi2, cpdi2_geometry, bilinear_at
  public :: cpdi2_folded, cpdi2_first_folded

contains

  !> Classic MPM basis: w_i = N_i(xp), gw_i = grad N_i(xp). need = 2.
  pure subroutine weights_linear(xp, origin, h, nb, i0, j0, w, gw, need)
    real(wp), intent(in) :: xp(2)           !! particle position [m]
    real(wp), intent(in) :: origin(2)       !! position of node (0, 0) [m]
    real(wp), intent(in) :: h               !! cell size [m]
    integer, intent(in) :: nb               !! nodes per direction of the block [-]
    integer, intent(out) :: i0              !! x index of the lower-left node of the block [-]
    integer, intent(out) :: j0              !! y index of the lower-left node of the block [-]
    real(wp), intent(out) :: w(nb*nb)       !! weights of the block nodes [-]
    real(wp), intent(out) :: gw(2, nb*nb)   !! gradients of the weights [1/m]
    integer, intent(out) :: need            !! nodes per direction the particle needs [-]
    real(wp) :: invh, s(2), n4(4), dn4(2, 4)
    integer :: kk(4)

    invh = 1.0_wp/h
    s = (xp - origin)*invh
    i0 = floor(s(1))
    j0 = floor(s(2))
    need = 2
    call cell_values(s(1) - real(i0, wp), s(2) - real(j0, wp), n4, dn4)
    if (need > nb) then
      w = 0.0_wp
      gw = 0.0_wp
    else if (nb == 2) then                       ! the usual block: every node is one of the cell's
      w = n4
      gw = dn4*invh
    else
      w = 0.0_wp
      gw = 0.0_wp
      kk = [1, 2, 1 + nb, 2 + nb]
      w(kk) = n4
      gw(:, kk) = dn4*invh
    end if
  end subroutine weights_linear

  !> uGIMP basis: w_i = average of N_i over the square [xp - half, xp + half] (closed form per
  !> direction, product of the two), gw_i = d w_i / d xp. need <= 3 when half <= h/2.
  pure subroutine weights_ugimp(xp, half, origin, h, nb, i0, j0, w, gw, need)
    real(wp), intent(in) :: xp(2)           !! particle centre [m]
    real(wp), intent(in) :: half(2)         !! half side lengths of the particle (>= 0) [m]
    real(wp), intent(in) :: origin(2)       !! position of node (0, 0) [m]
    real(wp), intent(in) :: h               !! cell size [m]
    integer, intent(in) :: nb               !! nodes per direction of the block [-]
    integer, intent(out) :: i0              !! x index of the lower-left node of the block [-]
    integer, intent(out) :: j0              !! y index of the lower-left node of the block [-]
    real(wp), intent(out) :: w(nb*nb)       !! weights of the block nodes [-]
    real(wp), intent(out) :: gw(2, nb*nb)   !! gradients of the weights [1/m]
    integer, intent(out) :: need            !! nodes per direction the particle needs [-]
    real(wp) :: invh, s(2), sl(2), q(2), wy, gy
    integer :: ihi, jhi, a, b, k

    invh = 1.0_wp/h
    s = (xp - origin)*invh
    sl = half*invh
    ! Touched nodes: those whose hat overlaps (s - sl, s + sl); at least the cell of s.
    call node_range(s(1) - sl(1), s(1) + sl(1), i0, ihi)
    call node_range(s(2) - sl(2), s(2) + sl(2), j0, jhi)
    ihi = max(ihi, floor(s(1)) + 1)
    jhi = max(jhi, floor(s(2)) + 1)
    need = max(ihi - i0, jhi - j0) + 1
    w = 0.0_wp
    gw = 0.0_wp
    if (need > nb) return
    q = 0.0_wp
    where (sl > 0.0_wp) q = 1.0_wp/sl
    ! Row 0 first holds the 1-D x factors (w: value, gw(1,:): derivative per unit of s); the
    ! other rows are their products with the y factors; row 0 is scaled last.
    do a = 0, ihi - i0
      call gimp_1d(s(1) - real(i0 + a, wp), sl(1), q(1), w(1 + a), gw(1, 1 + a))
    end do
    do b = 1, jhi - j0
      call gimp_1d(s(2) - real(j0 + b, wp), sl(2), q(2), wy, gy)
      do a = 0, ihi - i0
        k = 1 + a + nb*b
        w(k) = w(1 + a)*wy                    ! Bardenhagen & Kober 2004, uGIMP tensor product
        gw(1, k) = gw(1, 1 + a)*wy*invh
        gw(2, k) = w(1 + a)*gy*invh
      end do
    end do
    call gimp_1d(s(2) - real(j0, wp), sl(2), q(2), wy, gy)
    do a = 0, ihi - i0
      gw(2, 1 + a) = w(1 + a)*gy*invh
      gw(1, 1 + a) = gw(1, 1 + a)*wy*invh
      w(1 + a) = w(1 + a)*wy
    end do
  end subroutine weights_ugimp

  !> CPDI1 basis for the parallelogram centred at xp with half-vectors r1, r2: w_i = mean of
  !> N_i at the four corners; gw_i = average gradient of the corner interpolant of N_i.
  pure subroutine weights_cpdi1(xp, r1, r2, origin, h, nb, i0, j0, w, gw, need)
    real(wp), intent(in) :: xp(2)           !! particle centre [m]
    real(wp), intent(in) :: r1(2)           !! first half-vector of the domain [m]
    real(wp), intent(in) :: r2(2)           !! second half-vector of the domain [m]
    real(wp), intent(in) :: origin(2)       !! position of node (0, 0) [m]
    real(wp), intent(in) :: h               !! cell size [m]
    integer, intent(in) :: nb               !! nodes per direction of the block [-]
    integer, intent(out) :: i0              !! x index of the lower-left node of the block [-]
    integer, intent(out) :: j0              !! y index of the lower-left node of the block [-]
    real(wp), intent(out) :: w(nb*nb)       !! weights of the block nodes [-]
    real(wp), intent(out) :: gw(2, nb*nb)   !! gradients of the weights [1/m]
    integer, intent(out) :: need            !! nodes per direction the particle needs [-]
    real(wp) :: invh, sp(2), q1(2), q2(2), sc(2, 4), vol, inv_vol, wc(4), gc(2, 4)
    integer :: ihi, jhi

    invh = 1.0_wp/h
    sp = (xp - origin)*invh
    q1 = r1*invh
    q2 = r2*invh
    sc(:, 1) = sp - q1 - q2                   ! Sadeghirad et al. 2011, corners x1..x4
    sc(:, 2) = sp + q1 - q2
    sc(:, 3) = sp + q1 + q2
    sc(:, 4) = sp - q1 + q2
    call corner_block(sc, i0, j0, ihi, jhi, need)
    if (need > nb) then
      w = 0.0_wp
      gw = 0.0_wp
      return
    end if
    ! Signed volume: equals 4|r1 x r2| for r1 x r2 > 0 (r_k = F r_k0 keeps the sign of the
    ! initial pair), and keeps sum_i x_i (x) gw_i = I for either orientation.
    vol = 4.0_wp*(r1(1)*r2(2) - r1(2)*r2(1))  ! Sadeghirad et al. 2011, V_p = 4|r1 x r2|
    if (.not. abs(vol) > 0.0_wp) then
      call fill_nan(w, gw)
      return
    end if
    inv_vol = 1.0_wp/vol
    ! grad phi = (1/V) {[N(x1) - N(x3)] (r1y - r2y, r2x - r1x)
    !                  + [N(x2) - N(x4)] (r1y + r2y, -r1x - r2x)}   Sadeghirad et al. 2011
    gc(:, 1) = [r1(2) - r2(2), r2(1) - r1(1)]*inv_vol
    gc(:, 2) = [r1(2) + r2(2), -r1(1) - r2(1)]*inv_vol
    gc(:, 3) = -gc(:, 1)
    gc(:, 4) = -gc(:, 2)
    wc = 0.25_wp                              ! Sadeghirad et al. 2011, phi = mean of corners
    call scatter_corners(sc, wc, gc, i0, j0, ihi, jhi, nb, w, gw)
  end subroutine weights_cpdi1

  !> CPDI2 / CPDI-Q4 basis for the quadrilateral with corners xc (counter-clockwise): w_i =
  !> exact average over the quad of the isoparametric interpolant of N_i from its corner values;
  !> gw_i = average gradient of that interpolant (boundary-integral form). Optionally also the
  !> jmin of cpdi2_geometry (the folding check), from the same corner Jacobians.
  pure subroutine weights_cpdi2(xc, origin, h, nb, i0, j0, w, gw, need, jmin)
    real(wp), intent(in) :: xc(2, 4)        !! corners x1..x4, counter-clockwise [m]
    real(wp), intent(in) :: origin(2)       !! position of node (0, 0) [m]
    real(wp), intent(in) :: h               !! cell size [m]
    integer, intent(in) :: nb               !! nodes per direction of the block [-]
    integer, intent(out) :: i0              !! x index of the lower-left node of the block [-]
    integer, intent(out) :: j0              !! y index of the lower-left node of the block [-]
    real(wp), intent(out) :: w(nb*nb)       !! weights of the block nodes [-]
    real(wp), intent(out) :: gw(2, nb*nb)   !! gradients of the weights [1/m]
    integer, intent(out) :: need            !! nodes per direction the particle needs [-]
    real(wp), intent(out), optional :: jmin !! min corner Jacobian / (area/4), as cpdi2_geometry
    real(wp) :: invh, sc(2, 4), cj(4), area, wc(4), inv_2a, gc(2, 4), cen(2)
    integer :: ihi, jhi, c

    invh = 1.0_wp/h
    do c = 1, 4
      sc(:, c) = (xc(:, c) - origin)*invh
    end do
    call quad_jacobians(xc, cj, area)
    if (present(jmin)) then
      if (area > 0.0_wp) then                  ! (min, not minval: no NaN care needed here)
        jmin = min(cj(1), cj(2), cj(3), cj(4))/area
      else
        call cpdi2_geometry(xc, area, cen, jmin)
      end if
    end if
    call corner_block(sc, i0, j0, ihi, jhi, need)
    if (need > nb) then
      w = 0.0_wp
      gw = 0.0_wp
      return
    end if
    if (.not. abs(area) > 0.0_wp) then
      call fill_nan(w, gw)
      return
    end if
    call corner_weights(cj, area, wc)
    inv_2a = 0.5_wp/area
    ! grad phi = 1/(2V) [N1 (y24, x42) + N2 (y31, x13) + N3 (y42, x24) + N4 (y13, x31)]
    gc(:, 1) = [xc(2, 2) - xc(2, 4), xc(1, 4) - xc(1, 2)]*inv_2a   ! Sadeghirad et al. 2013
    gc(:, 2) = [xc(2, 3) - xc(2, 1), xc(1, 1) - xc(1, 3)]*inv_2a
    gc(:, 3) = -gc(:, 1)
    gc(:, 4) = -gc(:, 2)
    call scatter_corners(sc, wc, gc, i0, j0, ihi, jhi, nb, w, gw)
  end subroutine weights_cpdi2

  !> Geometry of a CPDI2 quadrilateral: signed area, area centroid and the smallest corner
  !> Jacobian of the bilinear map relative to its mean (1 for a parallelogram; <= 0 when the quad
  !> is folded, inverted, clockwise or non-convex).
  pure subroutine cpdi2_geometry(xc, area, centroid, jmin)
    real(wp), intent(in) :: xc(2, 4)        !! corners x1..x4, counter-clockwise [m]
    real(wp), intent(out) :: area           !! shoelace area, > 0 counter-clockwise [m^2]
    real(wp), intent(out) :: centroid(2)    !! area centroid [m]
    real(wp), intent(out) :: jmin           !! min corner Jacobian / (area/4) (2x2 reference) [-]
    real(wp) :: cj(4), wc(4), scale
    integer :: c

    call quad_jacobians(xc, cj, area)
    if (area > 0.0_wp) then
      call corner_weights(cj, area, wc)
      ! The centroid is the wc-weighted mean of the corners (what sum_i phi_i x_i gives);
      ! taken relative to corner 1 to avoid cancellation far from the origin.
      centroid = xc(:, 1)
      do c = 2, 4
        centroid = centroid + wc(c)*(xc(:, c) - xc(:, 1))
      end do
      jmin = minval(cj)/area
    else
      ! Inverted or degenerate: no meaningful centroid; report the corner mean and a
      ! non-positive jmin, scaled by the mean absolute corner Jacobian.
      centroid = 0.25_wp*(xc(:, 1) + xc(:, 2) + xc(:, 3) + xc(:, 4))
      scale = 0.25_wp*sum(abs(cj))
      if (scale > 0.0_wp) then
        jmin = min(minval(cj), 0.0_wp)/scale
      else
        jmin = 0.0_wp
      end if
    end if
  end subroutine cpdi2_geometry

  !> Whether a CPDI2 quadrilateral is folded: .not. jmin > 0 with the jmin of cpdi2_geometry,
  !> the same decision bit for bit (NaN or infinite corners included), without the centroid and
  !> corner weights that cpdi2_geometry also computes.
  pure logical function cpdi2_folded(xc) result(folded)
    real(wp), intent(in) :: xc(2, 4)        !! corners x1..x4, counter-clockwise [m]
    real(wp) :: cj(4), area

    call quad_jacobians(xc, cj, area)
    folded = .true.                         ! (area <= 0 or NaN: jmin <= 0 there)
    if (area > 0.0_wp) folded = .not. minval(cj)/area > 0.0_wp
  end function cpdi2_folded

  !> The first of particles 1..np whose CPDI2 domain, the corners xc(:, corner(:, ip)), is
  !> folded (cpdi2_folded), or 0 when none is.
  pure integer function cpdi2_first_folded(np, nc, corner, xc) result(first)
    integer, intent(in) :: np               !! particles [-]
    integer, intent(in) :: nc               !! corners [-]
    integer, intent(in) :: corner(4, np)    !! corner ids of each particle, counter-clockwise
    real(wp), intent(in) :: xc(2, nc)       !! corner positions [m]
    real(wp) :: xq(2, 4)
    integer :: ip

    first = 0
    do ip = 1, np
      xq(:, 1) = xc(:, corner(1, ip))
      xq(:, 2) = xc(:, corner(2, ip))
      xq(:, 3) = xc(:, corner(3, ip))
      xq(:, 4) = xc(:, corner(4, ip))
      if (cpdi2_folded(xq)) then
        first = ip
        return
      end if
    end do
  end function cpdi2_first_folded

  !> Bilinear weights N of the four nodes of the cell holding x; local order (0,0), (1,0),
  !> (0,1), (1,1) relative to the lower-left node (i0, j0).
  pure subroutine bilinear_at(x, origin, h, i0, j0, w4)
    real(wp), intent(in) :: x(2)            !! position [m]
    real(wp), intent(in) :: origin(2)       !! position of node (0, 0) [m]
    real(wp), intent(in) :: h               !! cell size [m]
    integer, intent(out) :: i0              !! x index of the lower-left node of the cell [-]
    integer, intent(out) :: j0              !! y index of the lower-left node of the cell [-]
    real(wp), intent(out) :: w4(4)          !! weights N of the four cell nodes [-]
    real(wp) :: s(2), fx, fy

    s = (x - origin)*(1.0_wp/h)
    i0 = floor(s(1))
    j0 = floor(s(2))
    fx = s(1) - real(i0, wp)
    fy = s(2) - real(j0, wp)
    w4 = [(1.0_wp - fx)*(1.0_wp - fy), fx*(1.0_wp - fy), (1.0_wp - fx)*fy, fx*fy]
  end subroutine bilinear_at

  ! ---------------------------------------------------------------------------------------------
  ! Private helpers. Scaled coordinates: node i sits at the integer i.

  ! Bilinear values and their gradients (per unit of scaled length) at local cell
  ! coordinates (fx, fy) in [0, 1]^2; order (0,0), (1,0), (0,1), (1,1).
  pure subroutine cell_values(fx, fy, n4, dn4)
    real(wp), intent(in) :: fx, fy          !! local coordinates in the cell [-]
    real(wp), intent(out) :: n4(4)          !! bilinear values [-]
    real(wp), intent(out) :: dn4(2, 4)      !! their gradients [1/h]
    real(wp) :: gx, gy

    gx = 1.0_wp - fx
    gy = 1.0_wp - fy
    n4 = [gx*gy, fx*gy, gx*fy, fx*fy]
    dn4(:, 1) = [-gy, -gx]
    dn4(:, 2) = [gy, -fx]
    dn4(:, 3) = [-fy, gx]
    dn4(:, 4) = [fy, fx]
  end subroutine cell_values

  ! Nodes whose hat overlaps the scaled interval [smin, smax] with positive length (or holds
  ! it, when smin = smax): lo = floor(smin), hi = ceil(smax).
  pure subroutine node_range(smin, smax, lo, hi)
    real(wp), intent(in) :: smin, smax      !! scaled interval [-]
    integer, intent(out) :: lo, hi          !! first and last node touched [-]
    lo = floor(smin)
    hi = ceiling(smax)
  end subroutine node_range

  ! Tightest block holding the cells of the four scaled corners; hi >= lo + 1 per direction.
  pure subroutine corner_block(sc, i0, j0, ihi, jhi, need)
    real(wp), intent(in) :: sc(2, 4)        !! scaled corners [-]
    integer, intent(out) :: i0, j0          !! lower-left node [-]
    integer, intent(out) :: ihi, jhi        !! upper-right node [-]
    integer, intent(out) :: need            !! nodes per direction needed [-]

    call node_range(min(sc(1, 1), sc(1, 2), sc(1, 3), sc(1, 4)), &
                    max(sc(1, 1), sc(1, 2), sc(1, 3), sc(1, 4)), i0, ihi)
    call node_range(min(sc(2, 1), sc(2, 2), sc(2, 3), sc(2, 4)), &
                    max(sc(2, 1), sc(2, 2), sc(2, 3), sc(2, 4)), j0, jhi)
    ihi = max(ihi, i0 + 1)
    jhi = max(jhi, j0 + 1)
    need = max(ihi - i0, jhi - j0) + 1
  end subroutine corner_block

  ! Weights and gradients from the corners: zero, then add weight wc(c)*N_i(x_c) and gradient
  ! N_i(x_c)*gc(:, c) to the four nodes of the cell of corner c, corner by corner. The cell is
  ! clamped so that a corner lying exactly on the last node line (local coordinate 1) stays
  ! inside the tight block.
  pure subroutine scatter_corners(sc, wc, gc, i0, j0, ihi, jhi, nb, w, gw)
    real(wp), intent(in) :: sc(2, 4)        !! scaled corner positions [-]
    real(wp), intent(in) :: wc(4)           !! corner weights [-]
    real(wp), intent(in) :: gc(2, 4)        !! corner gradient coefficients [1/m]
    integer, intent(in) :: i0, j0           !! lower-left node of the block [-]
    integer, intent(in) :: ihi, jhi         !! upper-right node of the block [-]
    integer, intent(in) :: nb               !! nodes per direction of the block [-]
    real(wp), intent(out) :: w(nb*nb)       !! weights [-]
    real(wp), intent(out) :: gw(2, nb*nb)   !! gradients [1/m]
    real(wp) :: fx, fy, n1, n2, n3, n4
    integer :: c, ic, jc, k

    if (nb == 3) then                       ! the usual width: zeroed in line, not by memset
      w(1:9) = 0.0_wp
      gw(:, 1:9) = 0.0_wp
    else
      w = 0.0_wp
      gw = 0.0_wp
    end if
    do c = 1, 4
      ic = min(floor(sc(1, c)), ihi - 1)
      jc = min(floor(sc(2, c)), jhi - 1)
      fx = sc(1, c) - real(ic, wp)
      fy = sc(2, c) - real(jc, wp)
      n1 = (1.0_wp - fx)*(1.0_wp - fy)      ! bilinear N of the cell's nodes at the corner
      n2 = fx*(1.0_wp - fy)
      n3 = (1.0_wp - fx)*fy
      n4 = fx*fy
      k = 1 + (ic - i0) + nb*(jc - j0)
      w(k) = w(k) + wc(c)*n1
      w(k + 1) = w(k + 1) + wc(c)*n2
      w(k + nb) = w(k + nb) + wc(c)*n3
      w(k + nb + 1) = w(k + nb + 1) + wc(c)*n4
      gw(:, k) = gw(:, k) + n1*gc(:, c)
      gw(:, k + 1) = gw(:, k + 1) + n2*gc(:, c)
      gw(:, k + nb) = gw(:, k + nb) + n3*gc(:, c)
      gw(:, k + nb + 1) = gw(:, k + nb + 1) + n4*gc(:, c)
    end do
  end subroutine scatter_corners

  ! 1-D uGIMP factor of one node: average of the hat H(u) = max(0, 1 - |u|) over
  ! [u - sl, u + sl] and its derivative d/du, u = (xp - x_i)/h. Written as the point value
  ! H(u) plus one correction per kink k = -1, 0, 1 of H lying inside the interval; this form
  ! has no cancellation for small sl and reduces to the linear hat when sl = 0.
  pure subroutine gimp_1d(u, sl, inv_sl, s, ds)
    real(wp), intent(in) :: u               !! particle centre minus node, scaled [-]
    real(wp), intent(in) :: sl              !! half length of the particle, scaled [-]
    real(wp), intent(in) :: inv_sl          !! 1/sl (0 when sl = 0) [-]
    real(wp), intent(out) :: s              !! averaged hat [-]
    real(wp), intent(out) :: ds             !! its derivative d/du [-]
    real(wp), parameter :: jump(-1:1) = [1.0_wp, -2.0_wp, 1.0_wp]   ! slope change of H at k
    real(wp) :: d, e
    integer :: k

    s = max(0.0_wp, 1.0_wp - abs(u))
    ! Right derivative of H (the kink terms below restore the average's smooth derivative).
    if (u >= -1.0_wp .and. u < 0.0_wp) then
      ds = 1.0_wp
    else if (u >= 0.0_wp .and. u < 1.0_wp) then
      ds = -1.0_wp
    else
      ds = 0.0_wp
    end if
    do k = -1, 1
      d = u - real(k, wp)
      if (abs(d) < sl) then
        e = sl - abs(d)
        s = s + jump(k)*e*e*(0.25_wp*inv_sl)               ! Bardenhagen & Kober 2004, GIMP
        ds = ds - jump(k)*merge(e, -e, d >= 0.0_wp)*(0.5_wp*inv_sl)  ! (average of the hat)
      end if
    end do
  end subroutine gimp_1d

  ! Corner Jacobians of the bilinear map from the unit square (corner a: J_a =
  ! (x_{a+1} - x_a) x (x_{a-1} - x_a)) and the signed area from the diagonals (= shoelace).
  pure subroutine quad_jacobians(xc, cj, area)
    real(wp), intent(in) :: xc(2, 4)        !! corners [m]
    real(wp), intent(out) :: cj(4)          !! Jacobian at corners 1..4 [m^2]
    real(wp), intent(out) :: area           !! signed area [m^2]
    real(wp) :: d21(2), d32(2), d34(2), d41(2), d31(2), d42(2)

    d21 = xc(:, 2) - xc(:, 1)
    d32 = xc(:, 3) - xc(:, 2)
    d34 = xc(:, 3) - xc(:, 4)
    d41 = xc(:, 4) - xc(:, 1)
    d31 = xc(:, 3) - xc(:, 1)
    d42 = xc(:, 4) - xc(:, 2)
    ! Sadeghirad et al. 2013: c1 = x21 y41 - y21 x41, c2 = x21 y32 - y21 x32,
    ! c3 = x34 y41 - y34 x41, c4 = x34 y32 - y34 x32 (c3 belongs to corner 4, c4 to corner 3).
    cj(1) = d21(1)*d41(2) - d21(2)*d41(1)
    cj(2) = d21(1)*d32(2) - d21(2)*d32(1)
    cj(3) = d34(1)*d32(2) - d34(2)*d32(1)
    cj(4) = d34(1)*d41(2) - d34(2)*d41(1)
    area = 0.5_wp*(d31(1)*d42(2) - d31(2)*d42(1))   ! shoelace area, diagonal form
  end subroutine quad_jacobians

  ! CPDI2 corner weights (1/V) int M_a dA from the corner Jacobians (cj in corner order).
  pure subroutine corner_weights(cj, area, wc)
    real(wp), intent(in) :: cj(4)           !! Jacobian at corners 1..4 [m^2]
    real(wp), intent(in) :: area            !! signed area, nonzero [m^2]
    real(wp), intent(out) :: wc(4)          !! corner weights, sum 1 [-]
    real(wp) :: f

    f = 1.0_wp/(36.0_wp*area)
    ! In the paper's c1..c4 (c3 = cj(4), c4 = cj(3)): weight of corner 1 is
    ! (4c1 + 2c2 + 2c3 + c4)/(36V), and so on.                      Sadeghirad et al. 2013
    wc(1) = (4.0_wp*cj(1) + 2.0_wp*cj(2) + cj(3) + 2.0_wp*cj(4))*f
    wc(2) = (2.0_wp*cj(1) + 4.0_wp*cj(2) + 2.0_wp*cj(3) + cj(4))*f
    wc(3) = (cj(1) + 2.0_wp*cj(2) + 4.0_wp*cj(3) + 2.0_wp*cj(4))*f
    wc(4) = (2.0_wp*cj(1) + cj(2) + 2.0_wp*cj(3) + 4.0_wp*cj(4))*f
  end subroutine corner_weights

  ! Mark the outputs invalid (zero-area domain).
  pure subroutine fill_nan(w, gw)
    real(wp), intent(inout) :: w(:)         !! weights [-]
    real(wp), intent(inout) :: gw(:, :)     !! gradients [1/m]
    real(wp) :: nan

    nan = ieee_value(0.0_wp, ieee_quiet_nan)
    w = nan
    gw = nan
  end subroutine fill_nan
end module mpm_basis
