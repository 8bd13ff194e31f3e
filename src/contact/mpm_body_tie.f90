!> Bonded bodies (`&contact law = 'bonded'`): the surfaces of two bodies that touch at t = 0 are
!! tied there for the whole run, by penalty springs between the points of one surface and the
!! material points of the other that they touched; what is not tied meets by the Coulomb law
!! of mpm_contact_law (`friction`). The ties of a case are made once (body_tie_make, at set-up
!! and again on a restart, from the particles at t = 0) and act as forces in step 3.
! SPDX-License-Identifier: MIT
!
! Basis 'cpdi2' (the input refuses the others): the surfaces are the bodies' boundary corners
! and edges (an edge of one particle that no other particle of its body shares). A boundary
! corner c of body A within h/2 of a boundary edge (b1, b2) of body B at t = 0 is tied to the
! point of that edge nearest to it, x_b = (1 - s) x_b1 + s x_b2 (s fixed, so the anchor is a
! material point of B), and so is every boundary corner of B within h/2 of A's edges: both
! surfaces are held, whichever is the finer. A tie holds the offset d0 = x_c - x_b of t = 0:
!
!     d = x_c - x_b - d0,   f = -k d on c, and +(1 - s) k d on b1, +s k d on b2,
!     energy k |d|^2 / 2   (in `strain`, as the walls' penalty; docs/method.md, "Energies"),
!
! with k = alpha (c / h)^2 m / 2, m the lesser of the corner's mass share and the anchor's
! ((1 - s) m_b1 + s m_b2; a quarter of the mass of each particle a corner belongs to), alpha
! and c those of the walls' penalty (mpm_surface_contact): the penalty frequency of the lighter
! side is the grid's own highest, and the half is for the two ties (one each way) that hold one
! stretch of surface. The forces go to the nodes with the weights N_i(x) of the velocity the
! corners move with (CPDI2: the bilinear interpolant of their own field's nodes), so that the
! springs' work is done on exactly the velocities that stretch them, and the energy is conserved
! to the order of the time integration (the walls' penalty argument): nothing is lost that the
! balance does not book. They sum to zero over the two bodies: momentum is exchanged, never
! created. As a spring, not a velocity constraint, the tie keeps its memory of where the
! surfaces were (a 'bonded' wall's argument, docs/method.md).
module mpm_body_tie
  use mpm_kinds, only: wp
  use mpm_basis, only: bilinear_at
  use mpm_grid, only: grid_t
  implicit none
  private
  public :: body_tie_t, body_tie_make, body_tie_forces, body_tie_energy, body_tie_nodes, &
            body_tie_step_energy

  !> The ties of a case (made at t = 0, never changed by a step).
  type :: body_tie_t
    integer :: n = 0                       !! ties
    integer, allocatable :: c(:)           !! the tied boundary corner (n)
    integer, allocatable :: e(:,:)         !! the two corners of the other body's edge (2, n),
                                           !! counter-clockwise in their particle
    real(wp), allocatable :: s(:)          !! the anchor's place along that edge (n) [-]
    real(wp), allocatable :: d0(:,:)       !! x_c - x_b at t = 0 (2, n) [m]
    real(wp), allocatable :: m(:)          !! mass of the tie's stiffness (n) [kg/m]
    integer, allocatable :: pair(:)        !! pair of bodies of the tie (history columns) (n)
    real(wp), allocatable :: sgn(:)        !! +1: c is the first body's of the pair, -1 the
                                           !! second's (n) [-]
  end type body_tie_t

contains

  !> The ties of the pairs of bodies with `bonded(i, j)`: the boundary corners of each within
  !! reach of the other's boundary edges at t = 0 (corners xc, particles' corners `corner` and
  !! bodies `body`, masses `mass`); pair(i, j) the pair's index for the history columns.
  pure subroutine body_tie_make(xc, corner, body, mass, bonded, pair, reach, tie)
    real(wp), intent(in) :: xc(:,:)        !! corner positions at t = 0 (2, nc) [m]
    integer, intent(in) :: corner(:,:)     !! corners of each particle (4, np)
    integer, intent(in) :: body(:)         !! body of each particle (np)
    real(wp), intent(in) :: mass(:)        !! particle masses (np) [kg/m]
    logical, intent(in) :: bonded(:,:)     !! the pairs tied (nbody, nbody)
    integer, intent(in) :: pair(:,:)       !! index of each pair (nbody, nbody)
    real(wp), intent(in) :: reach          !! largest distance of a tied corner (h/2) [m]
    type(body_tie_t), intent(out) :: tie   !! the ties
    real(wp), allocatable :: cm(:), load(:)
    integer, allocatable :: edges(:,:), ebody(:)
    integer :: nb, ia, ib, k, j
    real(wp) :: f
    nb = size(bonded, 1)
    allocate(tie%c(0), tie%e(2, 0), tie%s(0), tie%d0(2, 0), tie%m(0), tie%pair(0), tie%sgn(0))
    if (.not. any(bonded)) return
    allocate(cm(size(xc, 2)))
    cm = 0.0_wp
    do k = 1, size(body)
      do j = 1, 4
        cm(corner(j, k)) = cm(corner(j, k)) + 0.25_wp*mass(k)
      end do
    end do
    call boundary_edges(corner, body, size(xc, 2), edges, ebody)
    do ia = 1, nb
      do ib = 1, nb
        if (ia == ib .or. .not. bonded(ia, ib)) cycle
        call tie_side(xc, edges, ebody, cm, ia, ib, pair(ia, ib), reach, tie)
      end do
    end do
    tie%n = size(tie%c)
    ! the stiffness every corner carries, at most half of kf times its mass share: the ties
    ! through a corner (its own, and those anchored on its edges with the weights 1 - s, s)
    ! are scaled down together where they load it more
    allocate(load(size(xc, 2)))
    load = 0.0_wp
    do k = 1, tie%n
      load(tie%c(k)) = load(tie%c(k)) + tie%m(k)
      load(tie%e(1, k)) = load(tie%e(1, k)) + (1.0_wp - tie%s(k))*tie%m(k)
      load(tie%e(2, k)) = load(tie%e(2, k)) + tie%s(k)*tie%m(k)
    end do
    do k = 1, tie%n
      f = min(1.0_wp, 0.5_wp*cm(tie%c(k))/load(tie%c(k)))
      if (tie%s(k) < 1.0_wp) f = min(f, 0.5_wp*cm(tie%e(1, k))/load(tie%e(1, k)))
      if (tie%s(k) > 0.0_wp) f = min(f, 0.5_wp*cm(tie%e(2, k))/load(tie%e(2, k)))
      tie%m(k) = f*tie%m(k)
    end do
  end subroutine body_tie_make

  !> Tie the boundary corners of body ia to the nearest points of the boundary edges of body
  !! ib within reach (appended to tie).
  pure subroutine tie_side(xc, edges, ebody, cm, ia, ib, pair, reach, tie)
    real(wp), intent(in) :: xc(:,:)        !! corner positions at t = 0 (2, nc) [m]
    integer, intent(in) :: edges(:,:)      !! boundary edges (2, ne)
    integer, intent(in) :: ebody(:)        !! their bodies (ne)
    real(wp), intent(in) :: cm(:)          !! mass share of each corner (nc) [kg/m]
    integer, intent(in) :: ia, ib          !! the corners' body, the edges' body
    integer, intent(in) :: pair            !! the pair's index
    real(wp), intent(in) :: reach          !! largest distance of a tied corner [m]
    type(body_tie_t), intent(inout) :: tie !! the ties
    integer :: k, j, m, c, best, n
    real(wp) :: p(2), q(2), x(2), sb, sk, dist, dk, e(2)
    logical, allocatable :: done(:)
    allocate(done(size(xc, 2)))
    done = .false.
    do k = 1, size(ebody)
      if (ebody(k) /= ia) cycle
      do j = 1, 2
        c = edges(j, k)
        if (done(c)) cycle
        done(c) = .true.
        x = xc(:, c)
        best = 0
        dist = reach
        sb = 0.0_wp
        do m = 1, size(ebody)
          if (ebody(m) /= ib) cycle
          p = xc(:, edges(1, m))
          q = xc(:, edges(2, m))
          if (any(x < min(p, q) - dist) .or. any(x > max(p, q) + dist)) cycle
          e = q - p
          sk = max(0.0_wp, min(1.0_wp, dot_product(x - p, e)/dot_product(e, e)))
          dk = norm2(x - p - sk*e)
          if (dk < dist) then
            dist = dk
            best = m
            sb = sk
          end if
        end do
        if (best == 0) cycle
        p = xc(:, edges(1, best))
        q = xc(:, edges(2, best))
        n = size(tie%c) + 1
        tie%c = [tie%c, c]
        tie%e = reshape([tie%e, edges(:, best)], [2, n])
        tie%s = [tie%s, sb]
        tie%d0 = reshape([tie%d0, x - ((1.0_wp - sb)*p + sb*q)], [2, n])
        tie%m = [tie%m, min(cm(c), (1.0_wp - sb)*cm(edges(1, best)) + sb*cm(edges(2, best)))]
        tie%pair = [tie%pair, pair]
        tie%sgn = [tie%sgn, merge(1.0_wp, -1.0_wp, ia < ib)]
      end do
    end do
  end subroutine tie_side

  !> The boundary edges of every body: the edges (counter-clockwise in their particle) that
  !! no other particle of the body shares (2, ne), and the body of each (ne).
  pure subroutine boundary_edges(corner, body, nc, edges, ebody)
    integer, intent(in) :: corner(:,:)     !! corners of each particle (4, np)
    integer, intent(in) :: body(:)         !! body of each particle (np)
    integer, intent(in) :: nc              !! corners
    integer, allocatable, intent(out) :: edges(:,:), ebody(:)
    integer, allocatable :: first(:), list(:), fill(:)
    integer :: ip, j, a, b, k, ne, ip2
    logical :: shared
    allocate(first(nc + 1), fill(nc))          ! the particles of each corner (CSR)
    first = 0
    do ip = 1, size(body)
      do j = 1, 4
        first(corner(j, ip) + 1) = first(corner(j, ip) + 1) + 1
      end do
    end do
    first(1) = 1
    do k = 1, nc
      first(k + 1) = first(k + 1) + first(k)
    end do
    allocate(list(first(nc + 1) - 1))
    fill = first(1:nc)
    do ip = 1, size(body)
      do j = 1, 4
        list(fill(corner(j, ip))) = ip
        fill(corner(j, ip)) = fill(corner(j, ip)) + 1
      end do
    end do
    allocate(edges(2, 4*size(body)), ebody(4*size(body)))
    ne = 0
    do ip = 1, size(body)
      do j = 1, 4
        a = corner(j, ip)
        b = corner(1 + mod(j, 4), ip)
        shared = .false.
        do k = first(a), first(a + 1) - 1
          ip2 = list(k)
          if (ip2 == ip .or. body(ip2) /= body(ip)) cycle
          if (any(corner(:, ip2) == b)) shared = .true.
        end do
        if (shared) cycle
        ne = ne + 1
        edges(:, ne) = [a, b]
        ebody(ne) = body(ip)
      end do
    end do
    edges = edges(:, 1:ne)
    ebody = ebody(1:ne)
  end subroutine boundary_edges

  !> The ties' forces at the corners now (xc), added to the node forces of each corner's own
  !! field (field_of(c); nodes with mass above the cut-off), with kf = alpha (c / h)^2; the
  !! energy stored in them [J/m]; each pair's impulse over dt: its normal part (along the
  !! anchor edge's outward normal, > 0 pressing) and the impulse on its first body (imp(3,
  !! npair)); each tie's stretch d (2, n), for body_tie_step_energy.
  pure subroutine body_tie_forces(tie, xc, field_of, g, kf, dt, energy, imp, d_start)
    type(body_tie_t), intent(in) :: tie    !! the ties
    real(wp), intent(in) :: xc(:,:)        !! corner positions (2, nc) [m]
    integer, intent(in) :: field_of(:)     !! field of each corner (nc)
    type(grid_t), intent(inout) :: g       !! grid: node forces
    real(wp), intent(in) :: kf             !! stiffness per unit mass [1/s^2]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(out) :: energy        !! energy in the ties [J/m]
    real(wp), intent(inout) :: imp(:,:)    !! per pair: normal impulse, impulse on the first
                                           !! body (3, npair) [kg/s per m]
    real(wp), intent(out) :: d_start(:,:)  !! each tie's stretch (2, n) [m]
    integer :: k
    real(wp) :: f(2), d(2), e(2), nout(2), k_t
    energy = 0.0_wp
    do k = 1, tie%n
      d = tie_stretch(tie, xc, k)
      d_start(:, k) = d
      k_t = kf*tie%m(k)
      f = -k_t*d
      energy = energy + 0.5_wp*k_t*dot_product(d, d)
      call spread_force(g, xc(:, tie%c(k)), field_of(tie%c(k)), f)
      call spread_force(g, xc(:, tie%e(1, k)), field_of(tie%e(1, k)), &
                        -(1.0_wp - tie%s(k))*f)
      call spread_force(g, xc(:, tie%e(2, k)), field_of(tie%e(2, k)), -tie%s(k)*f)
      e = xc(:, tie%e(2, k)) - xc(:, tie%e(1, k))
      nout = [e(2), -e(1)]/max(norm2(e), tiny(1.0_wp))   ! out of the anchor's body
      imp(1, tie%pair(k)) = imp(1, tie%pair(k)) + dot_product(f, nout)*dt
      imp(2:3, tie%pair(k)) = imp(2:3, tie%pair(k)) + tie%sgn(k)*f*dt
    end do
  end subroutine body_tie_forces

  !> Force fv at x to the four nodes of its cell in field fl (those with mass), with the
  !! bilinear weights N_i(x) that a CPDI2 corner moves with.
  pure subroutine spread_force(g, x, fl, fv)
    type(grid_t), intent(inout) :: g       !! grid: node forces
    real(wp), intent(in) :: x(2)           !! the point [m]
    integer, intent(in) :: fl              !! its field
    real(wp), intent(in) :: fv(2)          !! the force [N/m]
    integer :: i0, j0, a, n
    real(wp) :: w4(4)
    call bilinear_at(x, g%origin, g%h, i0, j0, w4)
    if (i0 < 0 .or. j0 < 0 .or. i0 + 1 > g%nx - 1 .or. j0 + 1 > g%ny - 1) return
    do a = 1, 4
      n = 1 + i0 + mod(a - 1, 2) + g%nx*(j0 + (a - 1)/2) + g%nn*(fl - 1)
      if (g%mass(n) > g%mass_cut) g%force(:, n) = g%force(:, n) + w4(a)*fv
    end do
  end subroutine spread_force

  !> The nodes where the tied surfaces are (grid node ids of field 1, mark(nn)): those of the
  !! cells of every tied corner and its anchor's corners, and the ring of nodes around them
  !! (a contact node of the two bodies there is one of the tied surfaces). The contact law
  !! between the tied bodies is off at them (mpm_body_contact): the ties alone hold the
  !! surfaces there, in compression as in tension, and the law's inelastic impulse would take
  !! the energy of every vibration across the tie (two bonded elastic blocks lost 17 % of their
  !! energy in 2367 steps with it).
  pure subroutine body_tie_nodes(tie, xc, origin, h, nx, ny, mark)
    type(body_tie_t), intent(in) :: tie    !! the ties
    real(wp), intent(in) :: xc(:,:)        !! corner positions (2, nc) [m]
    real(wp), intent(in) :: origin(2)      !! position of node (0, 0) [m]
    real(wp), intent(in) :: h              !! cell size [m]
    integer, intent(in) :: nx, ny          !! nodes along x and y
    logical, intent(inout) :: mark(:)      !! marked nodes (nx ny)
    integer :: k, j, c, i0, j0, a, b
    real(wp) :: w4(4)
    do k = 1, tie%n
      do j = 1, 3
        c = tie%c(k)
        if (j > 1) c = tie%e(j - 1, k)
        call bilinear_at(xc(:, c), origin, h, i0, j0, w4)
        do b = max(0, j0 - 1), min(ny - 1, j0 + 2)
          do a = max(0, i0 - 1), min(nx - 1, i0 + 2)
            mark(1 + a + nx*b) = .true.
          end do
        end do
      end do
    end do
  end subroutine body_tie_nodes

  !> The energy stored in the ties with the corners at xc, 1/2 k |d|^2 [J/m].
  pure function body_tie_energy(tie, xc, kf) result(energy)
    type(body_tie_t), intent(in) :: tie    !! the ties
    real(wp), intent(in) :: xc(:,:)        !! corner positions (2, nc) [m]
    real(wp), intent(in) :: kf             !! stiffness per unit mass [1/s^2]
    real(wp) :: energy, d(2)
    integer :: k
    energy = 0.0_wp
    do k = 1, tie%n
      d = tie_stretch(tie, xc, k)
      energy = energy + 0.5_wp*kf*tie%m(k)*dot_product(d, d)
    end do
  end function body_tie_energy

  !> The ties' energy as the explicit step conserves it, as for the walls' CPDI2 points
  !! (mpm_surface_contact): 1/2 k d . d', the stretch d at the step's start (that of its
  !! force, body_tie_forces) and d' at its end, with the corners at xc [J/m].
  pure function body_tie_step_energy(tie, xc, kf, d_start) result(energy)
    type(body_tie_t), intent(in) :: tie    !! the ties
    real(wp), intent(in) :: xc(:,:)        !! corner positions at the step's end (2, nc) [m]
    real(wp), intent(in) :: kf             !! stiffness per unit mass [1/s^2]
    real(wp), intent(in) :: d_start(:,:)   !! each tie's stretch at the step's start (2, n) [m]
    real(wp) :: energy
    integer :: k
    energy = 0.0_wp
    do k = 1, tie%n
      energy = energy + 0.5_wp*kf*tie%m(k)*dot_product(d_start(:, k), tie_stretch(tie, xc, k))
    end do
  end function body_tie_step_energy

  !> Tie k's stretch: its corner from its anchor point on the other body's edge, less the
  !! offset at t = 0 [m].
  pure function tie_stretch(tie, xc, k) result(d)
    type(body_tie_t), intent(in) :: tie    !! the ties
    real(wp), intent(in) :: xc(:,:)        !! corner positions (2, nc) [m]
    integer, intent(in) :: k               !! the tie
    real(wp) :: d(2), xb(2)
    xb = (1.0_wp - tie%s(k))*xc(:, tie%e(1, k)) + tie%s(k)*xc(:, tie%e(2, k))
    d = xc(:, tie%c(k)) - xb - tie%d0(:, k)
  end function tie_stretch
end module mpm_body_tie
