!> Rigid-wall contact at the material surface: penalty forces on the surface points, friction
!! as a bounded tangential impulse.
! SPDX-License-Identifier: MIT
!
! The material surface is a set of points x_c: the CPDI2 domain corners, or the corners of each
! particle's CPDI1 parallelogram (x -+ F r10 -+ F r20) or uGIMP / linear square (x -+ half).
! Each point carries a share m_c of the particle mass (a quarter of each particle it is a
! corner of). The force of a point goes to the nodes with the weights of the velocity the
! code moves the point with, so that it does work on exactly the velocity that changes the
! gap and the contact energy is conserved to the order of the time integration:
! - a CPDI2 corner moves with the bilinear interpolant of the node velocities,
!   v_c = sum_i N_i(x_c) v_i: weights N_i(x_c);
! - a corner x_p + F r0 of the other bases (the domain deformed with the particle) moves as
!   the particle's position and F do, v_p + L F r0 = sum_i (S_ip + grad S_ip . r) v_i with
!   r = x_c - x_p: weights S_ip + grad S_ip . r (they sum to 1, so the momentum given is
!   still the force times dt). The grid's weights N_i(x_c) at such a corner did not match its
!   motion where the corner and its particle lie in different cells: a uGIMP block between
!   platens gained 4.7 % energy in plane stress (0.33 % with these weights), a linear one 5 %,
!   which stopped the run (docs/verification.md). Corners of the undeformed uGIMP square sink
!   into the plane as the particle compresses, with no force doing that work (5 % energy
!   error).
!
! Normal contact (docs/method.md, "Rigid walls and contact"): a point whose gap to the plane
! g_c = (x_c - x_w) . n is negative at the start of the step takes the force
!
!     f_c = k_c (-g_c) n,        k_c = alpha m_c c^2 / h^2,
!
! spread to the active nodes as above, in the same grid update as the internal forces. On a face
! of particles of size l (m_c = rho l^2 / 2 per length l) the penalty is as stiff as a layer 2 h^2
! / (alpha l) of the material, 2 h at one particle per cell and 4 h at two: the penetration under
! a pressure p is p 2 h^2 / (alpha l rho c^2), and a wall that speeds up loads the material about
! 2 h^2 / (alpha l c) late (a wave struck into a ring's wall at h = t/4, n_t = 8: up to 0.5 us;
! docs/fe_reference/README.md). &wall penalty p multiplies alpha for one wall (mpm_contact),
! shortening the layer and the lag by p and lowering the stable time step (cfl_auto divides by p).
! Where the face's corners lie on a row of nodes, sum_c k_c N_i is 0.5 to 0.56 alpha c^2 / h^2
! times the node's mass at two particles per cell (the node also carries the next row of corners):
! a penalty frequency of about 0.7 sqrt(alpha) c / h against the 2 c / h of a row of cells, so at
! the automatic cfl the stable time step is not lowered (at the stability study's limit, 1.75, a
! platen striking a flat face on grid lines stops the run, for a solid block whatever alpha:
! docs/method.md). The force is the gradient of the energy 1/2 k_c g_c^2: what the material puts
! into the contact it gets back at separation. The energy the balance counts after a step is, for
! a CPDI2 point, 1/2 k_c g_c g_c', the gap at the start of the step times that at its end
! (surface_step_energy), the explicit update's own invariant: 1/2 k_c g_c^2 alone lags it by dt/2
! f_c gdot_c (the corners of the other bases keep it). A kinematic constraint (the velocity of the
! point cut to what closes its gap) loses the kinetic energy of the nodes it stops at every
! impact, which costs an elastic bar a per cent of its rebound; that is why this code uses a
! penalty (docs/method.md).
!
! Friction acts on the points that carry a normal force, after the velocity update: the
! tangential impulse that stops the point's slip relative to the wall ('stick'), bounded by mu
! times the normal impulse ('coulomb'), with the same N_i / m_i distribution. Points that share
! nodes are solved together by projected Gauss-Seidel sweeps, in a fixed order.
!
! The momentum given to the material is sum_c lambda_c sum_i N_i over the active nodes,
! summed into the wall's reaction exactly (impulse on the wall = momentum taken from the body).
!
! A 'bonded' wall ties the points that lie within h/2 of it at t = 0 (surface_tie: their
! positions then, x0_c, kept for the whole run; the set-up makes them again from the input on
! a restart). A tied point is held by the same penalty stiffness to its anchor, the point x0_c
! carried with the wall (x0_c + s(t), s the wall's displacement since t = 0), in both
! directions along the wall and across it:
!
!     f_c = -k_c d_c,   d_c = x_c - x0_c - s(t),   energy 1/2 k_c |d_c|^2,
!
! pressed or pulled, so that it neither separates nor slips (by more than the elastic
! stretch of the tie, f / k_c). Its normal part is the penalty about the gap at t = 0, g_c -
! g0_c. The tangential part is a spring rather than the 'stick' impulse: a velocity constraint
! has no memory of where the point was, and under a sustained shear the grid's velocity
! after the MUSL re-map (which moves the points) does not keep it, so a ring sheared between
! two such walls crept by 15 % of the platen's travel at its bottom and gained 15 % energy;
! the spring pulls it back, and its work is the wall's work through the tie. Tied points
! take no friction; the points not tied meet the wall as with 'coulomb' (coefficient
! `friction`).
module mpm_surface_contact
  use mpm_kinds, only: wp
  use mpm_constants, only: BASIS_CPDI2, CONTACT_COULOMB, CONTACT_STICK, CONTACT_BONDED
  use mpm_particles, only: particles_t, particle_corners, corner_gaps
  use mpm_basis, only: bilinear_at
  implicit none
  private
  public :: surface_work_t, surface_points, surface_energy, surface_push, surface_friction, &
            surface_slip_loss, surface_step_energy, &
            contact_alpha, surface_reserve, corner_masses, surface_tie, surface_tied, &
            tie_force

  real(wp), parameter :: contact_alpha = 1.0_wp  !! penalty stiffness over the material's [-]
  integer, parameter :: max_sweeps = 200     !! Gauss-Seidel sweeps at most [-]
  integer, parameter :: scan_chunk = 1024    !! particles per task of the corner scan [-]
  real(wp), parameter :: sweep_tol = 1.0e-13_wp  !! relative change that ends the sweeps [-]
  integer, parameter, public :: curve_nc = 5  !! corners per curve point [-]
  real(wp), parameter, public :: untied = huge(1.0_wp)  !! anchor of a point not tied [m]

  !> Points in contact with one wall and the work arrays of their solve, grown as needed (no
  !! allocation in a steady run). A point is a corner behind the plane (CPDI2: a shared
  !! domain corner; the other bases: a corner of the particle's deformed domain).
  type :: surface_work_t
    integer :: npt = 0                     !! points gathered
    real(wp) :: gmin = 0.0_wp              !! the deepest gap among them (<= 0) [m]
    integer :: nnode = 4                   !! nodes per point (4, or the particle block nb^2)
    real(wp), allocatable :: xs(:,:)       !! CPDI2 corner positions, or (owner > 0) the corner's
                                           !! offset from its particle x_c - x_p (2, n) [m]
    integer, allocatable :: owner(:)       !! the particle of a point, or -(its corner id) (n)
    real(wp), allocatable :: fn(:)         !! normal penalty force (n) [N/m]
    real(wp), allocatable :: en(:)         !! penalty energy (n) [J/m]
    logical, allocatable :: tied(:)        !! the point is tied to a 'bonded' wall (n)
    real(wp), allocatable :: ft(:)         !! tied points: tangential tie force (n) [N/m]
    real(wp), allocatable :: x0(:,:)       !! 'bonded' wall: the position at t = 0 of each
                                           !! tied point, or untied (2, CPDI2: nc corners; the
                                           !! other bases: corner a of particle ip at 4 (ip -
                                           !! 1) + a); not allocated for the other laws [m]
    real(wp) :: shift(2) = 0.0_wp          !! the wall's displacement since t = 0 at the time
                                           !! of the points (set by the caller) [m]
    integer, allocatable :: node(:,:)      !! nodes of each point (nnode, n)
    real(wp), allocatable :: wt(:,:)       !! their weights N_i / m_i (nnode, n) [m/kg]
    real(wp), allocatable :: nw(:,:)       !! their weights N_i on active nodes (nnode, n) [-]
    real(wp), allocatable :: s(:)          !! sum_i N_i^2 / m_i of each point [m/kg]
    real(wp), allocatable :: lam(:,:)      !! normal and tangential impulses (2, n) [kg/s]
    real(wp), allocatable :: corner_mass(:)  !! CPDI2: mass share of each corner (nc) [kg/m]
    integer :: sweeps = 0                  !! sweeps taken by the last friction solve
    real(wp) :: de = 0.0_wp                !! the nodes' kinetic energy change by that solve
                                           !! (with the wall's work, the friction loss) [J/m]
    ! CPDI2 surface curve (mpm_surface_curve): a point is a quadrature point of the curve,
    ! a combination of up to five domain corners
    logical :: curve = .false.             !! the points are curve points (cid, phi, xq set)
    integer, allocatable :: cid(:,:)       !! the corners of each point, or 0 (curve_nc, n)
    real(wp), allocatable :: phi(:,:)      !! their coefficients: x = sum phi x_corner
                                           !! (curve_nc, n) [-]
    real(wp), allocatable :: xq(:,:,:)     !! their positions (2, curve_nc, n) [m]
    integer, allocatable :: nxt(:), prv(:) !! the next and previous corner along the body's
                                           !! boundary (counter-clockwise), 0 inside, -1 at a
                                           !! pinch (nc)
    integer, allocatable :: bnd(:)         !! the boundary corners (nxt or prv not 0), in order
    real(wp), allocatable :: dmin(:)       !! linear, uGIMP, CPDI1: each particle's deepest
                                           !! corner gap (np) [m]
    real(wp), allocatable :: dc(:)         !! gap of every corner to the wall (nc) [m]
    real(wp), allocatable :: dp(:)         !! gap of every corner's control point (nc) [m]
    integer, allocatable :: la(:), lb(:)   !! the neighbours that shift each corner's control
                                           !! point, or 0 (nc)
  end type surface_work_t

contains

  !> The surface points of particles p (basis `basis`) that lie behind the plane through xw
  !! with unit normal `normal` (into the material), with their penalty forces and energies
  !! (stiffness kf m_c per point), in wk (wk%npt of them), in corner or particle order.
  subroutine surface_points(p, basis, xw, normal, kf, par, wk)
    type(particles_t), intent(in) :: p     !! particles (positions, corners, F, masses)
    integer, intent(in) :: basis           !! BASIS_* code
    real(wp), intent(in) :: xw(2)          !! a point on the plane [m]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: kf             !! stiffness per unit point mass, alpha c^2/h^2 [1/s^2]
    logical, intent(in) :: par             !! the scan runs in parallel
    type(surface_work_t), intent(inout) :: wk  !! work arrays: the points
    integer :: ip, ic, a, nchunk, j
    real(wp) :: d, xq(2, 4), dq(4), gmin, fn, ft, en
    logical :: tie
    tie = allocated(wk%x0)
    wk%npt = 0
    wk%gmin = 0.0_wp
    wk%curve = .false.
    if (basis == BASIS_CPDI2) then
      call corner_masses(p, wk)
      do ic = 1, p%nc
        d = (p%xc(1, ic) - xw(1))*normal(1) + (p%xc(2, ic) - xw(2))*normal(2)
        wk%gmin = min(wk%gmin, d)
        if (tie) then                        ! a tied corner: the spring to its anchor
          if (wk%x0(1, ic) < untied) then
            call tie_force(p%xc(:, ic) - wk%x0(:, ic) - wk%shift, normal, &
                           kf*wk%corner_mass(ic), fn, ft, en)
            call push(-ic, p%xc(:, ic), fn, en, .true., ft)
            cycle
          end if
        end if
        if (d < 0.0_wp) call push(-ic, p%xc(:, ic), -kf*wk%corner_mass(ic)*d, &
                                  0.5_wp*kf*wk%corner_mass(ic)*d*d, .false., 0.0_wp)
      end do
      return
    end if
    ! the domain deformed with the particle (particle_corners, deformed: x -+ F r1 -+ F r2),
    ! so that a corner moves as the grid's velocity field at it to first order; the scan of
    ! every particle in parallel, then the few behind the plane gathered in particle order
    if (.not. allocated(wk%dmin)) allocate(wk%dmin(p%np))
    if (size(wk%dmin) /= p%np) then
      deallocate(wk%dmin)
      allocate(wk%dmin(p%np))
    end if
    gmin = 0.0_wp
    nchunk = (p%np + scan_chunk - 1)/scan_chunk
    !$omp parallel do default(none) schedule(static) shared(p, basis, xw, normal, wk, nchunk) &
    !$omp   private(ic) reduction(min: gmin) if(par)
    do ic = 1, nchunk
      call corner_gaps(p, 1 + (ic - 1)*scan_chunk, min(ic*scan_chunk, p%np), basis, p%np, &
                       p%x, p%F, p%half, p%r10, p%r20, xw, normal, wk%dmin, gmin)
    end do
    !$omp end parallel do
    wk%gmin = gmin
    do ip = 1, p%np
      j = 4*(ip - 1)
      if (wk%dmin(ip) >= 0.0_wp) then
        if (.not. tie) cycle
        if (all(wk%x0(1, j + 1:j + 4) == untied)) cycle
      end if
      xq = particle_corners(p, ip, basis, deformed=.true.)
      dq = [(dot_product(xq(:, a) - xw, normal), a = 1, 4)]
      do a = 1, 4
        if (tie) then                        ! a tied corner: the spring to its anchor
          if (wk%x0(1, j + a) < untied) then
            call tie_force(xq(:, a) - wk%x0(:, j + a) - wk%shift, normal, &
                           kf*0.25_wp*p%mass(ip), fn, ft, en)
            call push(ip, xq(:, a) - p%x(:, ip), fn, en, .true., ft)
            cycle
          end if
        end if
        if (dq(a) < 0.0_wp) call push(ip, xq(:, a) - p%x(:, ip), -kf*0.25_wp*p%mass(ip)*dq(a), &
                                      0.125_wp*kf*p%mass(ip)*dq(a)*dq(a), .false., 0.0_wp)
      end do
    end do
  contains
    subroutine push(owner, xp, force, energy, tied, tforce)
      integer, intent(in) :: owner
      real(wp), intent(in) :: xp(2), force, energy, tforce
      logical, intent(in) :: tied
      call surface_reserve(wk, wk%npt + 1)
      wk%npt = wk%npt + 1
      wk%owner(wk%npt) = owner
      wk%xs(:, wk%npt) = xp
      wk%fn(wk%npt) = force
      wk%en(wk%npt) = energy
      wk%tied(wk%npt) = tied
      wk%ft(wk%npt) = tforce
    end subroutine push
  end subroutine surface_points

  !> The energy stored in the contact of the points gathered [J/m].
  pure function surface_energy(wk) result(e)
    type(surface_work_t), intent(in) :: wk !! points
    real(wp) :: e
    e = sum(wk%en(1:wk%npt))
  end function surface_energy

  !> The energy stored in the contact of the points gathered, as the step's explicit update
  !! conserves it [J/m]: per CPDI2 point 1/2 k_c g_c g_c', the gap at the start of the step
  !! (that of its force) times the gap at its end, g_c' = g_c + dt gdot_c (gdot_c = (v_c -
  !! v_w) . n, v_c = sum_i N_i v_i the velocity the corners move with); in general e_c - dt/2
  !! f_c . (v_c - v_w), which is 1/2 k_c d_c . d_c' for a tied point; never below zero (a point
  !! that leaves the wall within the step). The energy at the start of the step alone, e_c, is
  !! off by dt/2 f_c gdot_c, the lag between the force and the velocity it makes: a thin wall
  !! thrown off a platen within a few steps showed 5 % growth from it (docs/method.md, "Normal
  !! contact"). The corner of another basis (a particle's point, owner > 0) moves with its
  !! particle's position and F, which the schemes update from different velocity fields (USF:
  !! F from the next step's mapped velocity), not with sum_i W_i v_i: it keeps e_c (with the
  !! pairing a uGIMP disc crushed by 'bonded' platens under USF, whose ties carry a lasting
  !! force, missed its balance by 2.1 % instead of 0.24 %). So does a point without active
  !! nodes (no force). Call after the step (surface_push set the weights; vel is the node
  !! velocity the corners moved with).
  pure function surface_step_energy(wk, normal, vwall, vel, dt) result(e)
    type(surface_work_t), intent(in) :: wk !! points, weights (surface_push)
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: vwall(2)       !! wall velocity over the step [m/s]
    real(wp), intent(in) :: vel(:,:)       !! node velocity (2, nn) [m/s]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp) :: e
    integer :: k, a
    real(wp) :: vr(2), f(2)
    e = 0.0_wp
    do k = 1, wk%npt
      if (wk%owner(k) > 0 .or. .not. wk%s(k) > 0.0_wp) then
        e = e + wk%en(k)
        cycle
      end if
      vr = -vwall
      do a = 1, wk%nnode
        if (wk%nw(a, k) /= 0.0_wp) vr = vr + wk%nw(a, k)*vel(:, wk%node(a, k))
      end do
      f = wk%fn(k)*normal
      if (wk%tied(k)) f = f + wk%ft(k)*[-normal(2), normal(1)]
      e = e + max(0.0_wp, wk%en(k) - 0.5_wp*dt*(f(1)*vr(1) + f(2)*vr(2)))
    end do
  end function surface_step_energy

  !> The penalty forces of the points gathered, added to the node forces of the active nodes
  !! (CPDI2 corners: the bilinear weights at the corner; the corners of the other bases:
  !! their particle's weights and gradients of this step extrapolated to the corner,
  !! w + gw . (x_c - x_p), on the particle's block blk, nb); impulse = the momentum they give
  !! the material over dt. Sets up the weights and the normal impulses that surface_friction
  !! reads. With several velocity fields, each point acts on the nodes of its own field.
  subroutine surface_push(wk, origin, h, nx, ny, mass, mass_cut, nb, blk, w, gw, normal, dt, &
                          force, impulse, nf, pfield, cfield)
    type(surface_work_t), intent(inout) :: wk  !! points; weights and normal impulses set
    real(wp), intent(in) :: origin(2)      !! position of node (0, 0) [m]
    real(wp), intent(in) :: h              !! cell size [m]
    integer, intent(in) :: nx, ny          !! nodes along x and y
    real(wp), intent(in) :: mass(:)        !! node mass [kg/m]
    real(wp), intent(in) :: mass_cut       !! active nodes have mass above this [kg/m]
    integer, intent(in) :: nb              !! particle block width (nodes per direction)
    integer, intent(in) :: blk(:,:)        !! lower-left node of each particle's block (2, np)
    real(wp), intent(in) :: w(:,:)         !! particle weights (nb*nb, np) [-]
    real(wp), intent(in) :: gw(:,:,:)      !! their gradients (2, nb*nb, np) [1/m]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(inout) :: force(:,:)  !! node force (2, nn) [N/m]
    real(wp), intent(out) :: impulse(2)    !! momentum given to the material [kg/s per m]
    integer, intent(in), optional :: nf    !! velocity fields (mpm_body_contact; default 1)
    integer, intent(in), allocatable, optional :: pfield(:)  !! field of each particle (nf > 1)
    integer, intent(in), allocatable, optional :: cfield(:)  !! field of each CPDI2 corner
    integer :: k, a, b, n, i0, j0, ip, off, nfl
    real(wp) :: w4(4), tang(2)
    tang = [-normal(2), normal(1)]
    nfl = 1
    if (present(nf)) nfl = nf
    impulse = 0.0_wp
    if (wk%npt == 0) return
    wk%nnode = 4
    if (wk%owner(1) > 0) wk%nnode = nb*nb
    if (wk%curve) wk%nnode = 4*curve_nc
    call grow_nodes(wk, size(wk%fn))
    off = 0
    do k = 1, wk%npt
      wk%s(k) = 0.0_wp
      wk%lam(:, k) = 0.0_wp
      wk%node(:, k) = 0
      wk%wt(:, k) = 0.0_wp
      wk%nw(:, k) = 0.0_wp
      ip = wk%owner(k)
      if (nfl > 1) then                      ! the nodes of the point's own field
        if (ip > 0) then
          off = nx*ny*(pfield(ip) - 1)
        else
          off = nx*ny*(cfield(-ip) - 1)
        end if
      end if
      if (wk%curve) then
        call curve_weights(k)
      else if (ip > 0) then
        do b = 0, nb - 1
          do a = 0, nb - 1
            n = 1 + a + nb*b
            wk%node(n, k) = 1 + blk(1, ip) + a + nx*(blk(2, ip) + b) + off
            wk%nw(n, k) = w(n, ip) + gw(1, n, ip)*wk%xs(1, k) + gw(2, n, ip)*wk%xs(2, k)
          end do
        end do
      else
        call bilinear_at(wk%xs(:, k), origin, h, i0, j0, w4)
        if (i0 < 0 .or. j0 < 0 .or. i0 + 1 > nx - 1 .or. j0 + 1 > ny - 1) cycle
        wk%node(:, k) = [1 + i0 + nx*j0, 2 + i0 + nx*j0, 1 + i0 + nx*(j0 + 1), &
                         2 + i0 + nx*(j0 + 1)] + off
        wk%nw(:, k) = w4
      end if
      do a = 1, wk%nnode
        n = wk%node(a, k)
        if (n == 0) then                     ! an empty slot (curve points)
          wk%nw(a, k) = 0.0_wp
          cycle
        end if
        if (wk%nw(a, k) == 0.0_wp .or. .not. mass(n) > mass_cut) then
          wk%nw(a, k) = 0.0_wp
          cycle
        end if
        wk%wt(a, k) = wk%nw(a, k)/mass(n)
        wk%s(k) = wk%s(k) + wk%nw(a, k)*wk%wt(a, k)
      end do
      if (.not. wk%s(k) > 0.0_wp) cycle
      wk%lam(1, k) = wk%fn(k)*dt
      do a = 1, wk%nnode
        if (wk%nw(a, k) == 0.0_wp) cycle
        n = wk%node(a, k)
        force(:, n) = force(:, n) + (wk%nw(a, k)*wk%fn(k))*normal
        if (wk%tied(k)) force(:, n) = force(:, n) + (wk%nw(a, k)*wk%ft(k))*tang  ! along too
      end do
      impulse = impulse + (wk%fn(k)*dt*sum(wk%nw(1:wk%nnode, k)))*normal
      if (wk%tied(k)) impulse = impulse + (wk%ft(k)*dt*sum(wk%nw(1:wk%nnode, k)))*tang
    end do
  contains
    !> Curve point k: the weights sum_m phi_m N_i(x_m) of the nodes of its corners (each
    !! node once, so that s = sum N_i^2 / m_i is the point's inverse mass).
    subroutine curve_weights(k)
      integer, intent(in) :: k
      integer :: m, q, r, c, i0c, j0c
      real(wp) :: wc(4)
      do m = 1, curve_nc
        c = wk%cid(m, k)
        if (c == 0 .or. wk%phi(m, k) == 0.0_wp) cycle
        call bilinear_at(wk%xq(:, m, k), origin, h, i0c, j0c, wc)
        if (i0c < 0 .or. j0c < 0 .or. i0c + 1 > nx - 1 .or. j0c + 1 > ny - 1) cycle
        if (nfl > 1) off = nx*ny*(cfield(c) - 1)
        wk%node(4*m - 3:4*m, k) = [1 + i0c + nx*j0c, 2 + i0c + nx*j0c, &
                                   1 + i0c + nx*(j0c + 1), 2 + i0c + nx*(j0c + 1)] + off
        wk%nw(4*m - 3:4*m, k) = wk%phi(m, k)*wc
      end do
      do q = 2, 4*curve_nc                 ! merge repeated nodes into their first slot
        if (wk%node(q, k) == 0) cycle
        do r = 1, q - 1
          if (wk%node(r, k) /= wk%node(q, k)) cycle
          wk%nw(r, k) = wk%nw(r, k) + wk%nw(q, k)
          wk%nw(q, k) = 0.0_wp
          wk%node(q, k) = 0
          exit
        end do
      end do
    end subroutine curve_weights
  end subroutine surface_push

  !> Friction of the points surface_push pushed: the tangential impulse that stops each
  !! point's slip relative to the wall ('stick'), bounded by friction times its normal impulse
  !! ('coulomb'); node velocities change in place, and dvel by the same amount. impulse = the
  !! momentum given to the material. 'bonded': the points not tied take the Coulomb bound; the
  !! tied ones no friction (their tie acts along the wall, surface_push).
  subroutine surface_friction(wk, law, friction, normal, vwall, vel, dvel, impulse)
    type(surface_work_t), intent(inout) :: wk  !! points, weights, normal impulses
    integer, intent(in) :: law             !! CONTACT_COULOMB, CONTACT_STICK or CONTACT_BONDED
    real(wp), intent(in) :: friction       !! Coulomb coefficient [-]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: vwall(2)       !! wall velocity over the step [m/s]
    real(wp), intent(inout) :: vel(:,:)    !! node velocity (2, nn) [m/s]
    real(wp), intent(inout) :: dvel(:,:)   !! node velocity change of the step (2, nn) [m/s]
    real(wp), intent(out) :: impulse(2)    !! momentum given to the material [kg/s per m]
    integer :: k, a, n, sweep
    real(wp) :: tang(2), vc(2), lt, dlt, change, vscale, d(2)
    impulse = 0.0_wp
    wk%sweeps = 0
    wk%de = 0.0_wp
    if (law /= CONTACT_COULOMB .and. law /= CONTACT_STICK .and. law /= CONTACT_BONDED) return
    tang = [-normal(2), normal(1)]
    vscale = sqrt(dot_product(vwall, vwall))
    do k = 1, wk%npt
      wk%lam(2, k) = 0.0_wp
      do a = 1, wk%nnode
        if (wk%nw(a, k) /= 0.0_wp) vscale = max(vscale, maxval(abs(vel(:, wk%node(a, k)))))
      end do
    end do
    vscale = max(vscale, tiny(1.0_wp))
    do sweep = 1, max_sweeps
      change = 0.0_wp
      do k = 1, wk%npt
        if (.not. wk%s(k) > 0.0_wp) cycle
        if (.not. wk%lam(1, k) > 0.0_wp .or. wk%tied(k)) cycle
        vc = 0.0_wp
        do a = 1, wk%nnode
          if (wk%nw(a, k) /= 0.0_wp) vc = vc + wk%nw(a, k)*vel(:, wk%node(a, k))
        end do
        lt = wk%lam(2, k) - dot_product(vc - vwall, tang)/wk%s(k)
        if (law == CONTACT_COULOMB .or. law == CONTACT_BONDED) lt = &
          max(-friction*wk%lam(1, k), min(friction*wk%lam(1, k), lt))
        dlt = lt - wk%lam(2, k)
        if (dlt == 0.0_wp) cycle
        wk%lam(2, k) = lt
        do a = 1, wk%nnode
          if (wk%wt(a, k) == 0.0_wp) cycle
          n = wk%node(a, k)
          d = wk%wt(a, k)*dlt*tang           ! node mass nw / wt: its kinetic energy change
          wk%de = wk%de + wk%nw(a, k)/wk%wt(a, k)*(dot_product(vel(:, n), d) + &
                                                   0.5_wp*dot_product(d, d))
          vel(:, n) = vel(:, n) + d
          dvel(:, n) = dvel(:, n) + d
        end do
        change = max(change, abs(dlt)*wk%s(k))
      end do
      wk%sweeps = sweep
      if (change <= sweep_tol*vscale) exit
    end do
    do k = 1, wk%npt
      if (wk%s(k) > 0.0_wp) impulse = impulse + wk%lam(2, k)*sum(wk%nw(1:wk%nnode, k))*tang
    end do
  end subroutine surface_friction

  !> The energy the friction of the points took over the step [J/m]: each point's
  !! tangential impulse times the slip it leaves, sum_k lambda_k t . sum_i N_i (v_wall -
  !! v_i) over the node velocities v_i after the solve, which is the wall's work through
  !! the friction less the work on the material's velocity as the step leaves it (the
  !! velocity the stress update and the positions see). 'stick' leaves no slip and takes
  !! nothing; 'coulomb' takes mu times the normal impulse times the slip. (The nodes' kinetic
  !! energy change, wk%de, is not the loss: a stick point re-stopped every step would count
  !! the velocity the internal forces give its nodes in each step, which the stress update
  !! never sees, as lost.)
  pure function surface_slip_loss(wk, normal, vwall, vel) result(e)
    type(surface_work_t), intent(in) :: wk !! points, weights, impulses (after the solve)
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: vwall(2)       !! wall velocity over the step [m/s]
    real(wp), intent(in) :: vel(:,:)       !! node velocity (2, nn) [m/s]
    real(wp) :: e
    integer :: k, a
    real(wp) :: tang(2), slip
    tang = [-normal(2), normal(1)]
    e = 0.0_wp
    do k = 1, wk%npt
      if (.not. wk%s(k) > 0.0_wp .or. wk%lam(2, k) == 0.0_wp) cycle
      slip = 0.0_wp
      do a = 1, wk%nnode
        if (wk%nw(a, k) /= 0.0_wp) slip = slip + wk%nw(a, k)* &
                                         dot_product(vwall - vel(:, wk%node(a, k)), tang)
      end do
      e = e + wk%lam(2, k)*slip
    end do
  end function surface_slip_loss

  !> A 'bonded' wall at t = 0: the surface points of particles p (basis `basis`: CPDI2
  !! corners, else the corners of each particle's deformed domain) that lie less than `reach`
  !! (h/2) in front of the plane through xw with unit normal `normal` (or behind it) are tied,
  !! with their positions now as anchors (wk%x0; untied for the others).
  subroutine surface_tie(p, basis, xw, normal, reach, wk)
    type(particles_t), intent(in) :: p     !! particles at t = 0
    integer, intent(in) :: basis           !! BASIS_* code
    real(wp), intent(in) :: xw(2)          !! a point on the plane [m]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: reach          !! largest gap of a tied point [m]
    type(surface_work_t), intent(inout) :: wk  !! x0 set
    integer :: ic, ip, a
    real(wp) :: xq(2, 4)
    if (allocated(wk%x0)) deallocate(wk%x0)
    if (basis == BASIS_CPDI2) then
      allocate(wk%x0(2, p%nc))
      do ic = 1, p%nc
        wk%x0(:, ic) = anchor(p%xc(:, ic))
      end do
      return
    end if
    allocate(wk%x0(2, 4*p%np))
    do ip = 1, p%np
      xq = particle_corners(p, ip, basis, deformed=.true.)
      do a = 1, 4
        wk%x0(:, 4*(ip - 1) + a) = anchor(xq(:, a))
      end do
    end do
  contains
    pure function anchor(x) result(x0)
      real(wp), intent(in) :: x(2)
      real(wp) :: x0(2)
      x0 = x
      if (.not. dot_product(x - xw, normal) < reach) x0 = untied
    end function anchor
  end subroutine surface_tie

  !> The tie of a point displaced by d from its anchor (stiffness k): the normal and
  !! tangential (along [-n_y, n_x]) parts of the force -k d, and the energy 1/2 k |d|^2.
  pure subroutine tie_force(d, normal, k, fn, ft, en)
    real(wp), intent(in) :: d(2)           !! position less the anchor [m]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: k              !! stiffness [N/m per m]
    real(wp), intent(out) :: fn, ft        !! force along the normal and the wall [N/m]
    real(wp), intent(out) :: en            !! energy [J/m]
    fn = -k*(d(1)*normal(1) + d(2)*normal(2))
    ft = -k*(-d(1)*normal(2) + d(2)*normal(1))
    en = 0.5_wp*k*(d(1)*d(1) + d(2)*d(2))
  end subroutine tie_force

  !> The number of points tied to the wall (0 without a tie).
  pure integer function surface_tied(wk)
    type(surface_work_t), intent(in) :: wk !! work arrays (x0)
    surface_tied = 0
    if (allocated(wk%x0)) surface_tied = count(wk%x0(1, :) < untied)
  end function surface_tied

  !> CPDI2: each corner's share of the particle mass, a quarter of each particle it belongs
  !! to (computed once: particle masses do not change).
  subroutine corner_masses(p, wk)
    type(particles_t), intent(in) :: p     !! particles
    type(surface_work_t), intent(inout) :: wk  !! corner_mass set
    integer :: ip, a
    if (allocated(wk%corner_mass)) then
      if (size(wk%corner_mass) == p%nc) return
      deallocate(wk%corner_mass)
    end if
    allocate(wk%corner_mass(p%nc))
    wk%corner_mass = 0.0_wp
    do ip = 1, p%np
      do a = 1, 4
        wk%corner_mass(p%corner(a, ip)) = wk%corner_mass(p%corner(a, ip)) + 0.25_wp*p%mass(ip)
      end do
    end do
  end subroutine corner_masses

  !> Make room for n points (at least; doubling), keeping the points gathered so far (and,
  !! for curve points, their corners).
  subroutine surface_reserve(wk, n)
    type(surface_work_t), intent(inout) :: wk  !! work arrays
    integer, intent(in) :: n               !! points
    real(wp), allocatable :: tx(:,:), tf(:), te(:), tp(:,:), tq(:,:,:)
    integer, allocatable :: to(:), tc(:,:)
    logical, allocatable :: tt(:)
    real(wp), allocatable :: tg(:)
    integer :: m
    logical :: main, curve
    main = .not. allocated(wk%fn)
    if (.not. main) main = size(wk%fn) < n
    curve = .false.
    if (wk%curve) curve = .not. allocated(wk%cid)
    if (wk%curve .and. .not. curve) curve = main .or. size(wk%cid, 2) < size(wk%fn)
    if (.not. (main .or. curve)) return
    m = max(n, 64)
    if (allocated(wk%fn)) m = max(m, size(wk%fn))
    if (main .and. allocated(wk%fn)) m = max(m, 2*size(wk%fn))
    if (main) then
      allocate(tx(2, m), tf(m), te(m), to(m), tt(m), tg(m))
      if (wk%npt > 0) then
        tx(:, 1:wk%npt) = wk%xs(:, 1:wk%npt)
        tf(1:wk%npt) = wk%fn(1:wk%npt)
        te(1:wk%npt) = wk%en(1:wk%npt)
        to(1:wk%npt) = wk%owner(1:wk%npt)
        tt(1:wk%npt) = wk%tied(1:wk%npt)
        tg(1:wk%npt) = wk%ft(1:wk%npt)
      end if
      call move_alloc(tx, wk%xs)
      call move_alloc(tf, wk%fn)
      call move_alloc(te, wk%en)
      call move_alloc(to, wk%owner)
      call move_alloc(tt, wk%tied)
      call move_alloc(tg, wk%ft)
    end if
    if (.not. wk%curve) return
    allocate(tc(curve_nc, m), tp(curve_nc, m), tq(2, curve_nc, m))
    if (wk%npt > 0) then
      tc(:, 1:wk%npt) = wk%cid(:, 1:wk%npt)
      tp(:, 1:wk%npt) = wk%phi(:, 1:wk%npt)
      tq(:, :, 1:wk%npt) = wk%xq(:, :, 1:wk%npt)
    end if
    call move_alloc(tc, wk%cid)
    call move_alloc(tp, wk%phi)
    call move_alloc(tq, wk%xq)
  end subroutine surface_reserve

  !> Node lists for n points of wk%nnode nodes each.
  subroutine grow_nodes(wk, n)
    type(surface_work_t), intent(inout) :: wk  !! work arrays
    integer, intent(in) :: n               !! points
    if (allocated(wk%s)) then
      if (size(wk%s) >= n .and. size(wk%node, 1) == wk%nnode) return
      deallocate(wk%node, wk%wt, wk%nw, wk%s, wk%lam)
    end if
    allocate(wk%node(wk%nnode, n), wk%wt(wk%nnode, n), wk%nw(wk%nnode, n), wk%s(n), &
             wk%lam(2, n))
  end subroutine grow_nodes

end module mpm_surface_contact
