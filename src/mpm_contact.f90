!> Wall contact on the grid (steps 3 and 5 of docs/algorithm.md): the gap of every node to
!! each wall (the material surface, not the node, must reach the plane), the node rule, and the
!! reactions (impulse, force, work) of the walls. mpm_walls keeps the wall type and its
!! prescribed motion; this module is where a contact law acts.
! SPDX-License-Identifier: MIT
!
! The node velocity update (momentum and force over mass, damping) runs in the same pass over
! the live nodes as the contact rule, so both grid loops live here: grid_velocity_walls (the
! USF velocity and the MUSL re-map: no reactions) and grid_update_walls (step 3: the momentum
! the walls add is their impulse). Node sums (impulses, damping) are formed per live span and
! added in span order, so they do not depend on the thread count.
module mpm_contact
  use mpm_kinds, only: wp
  use mpm_constants, only: BASIS_CPDI1, BASIS_CPDI2, CONTACT_SLIP
  use mpm_particles, only: particles_t, particle_corners
  use mpm_grid, only: grid_t
  use mpm_tiles, only: tiles_t, tiles_span
  use mpm_walls, only: wall_t, wall_velocity, wall_constrain_node, wall_travel
  use mpm_state, only: params_t, state_t, work_t, chunk
  implicit none
  private
  public :: grid_velocity_walls, grid_update_walls, contact_begin_step, contact_reactions

contains

  !> Start of a step: the walls at time t (their planes moved by the prescribed motion), and
  !! no impulse yet.
  subroutine contact_begin_step(st)
    type(state_t), intent(inout) :: st     !! state: walls
    integer :: k
    do k = 1, st%nwall
      st%walls(k)%point = st%walls(k)%point0 - wall_travel(st%walls(k), st%t)*st%walls(k)%normal
      st%walls(k)%impulse = 0.0_wp
    end do
    ! wall_travel is the travel along -normal; the tangential part of the motion does not move
    ! the plane, so point0 + travel*(-normal) is a point on the current plane.
  end subroutine contact_begin_step

  !> End of a step (t is the new time): each wall's force on the material side = -impulse/dt,
  !! its impulse summed for the history, its work impulse . v_wall(t - dt/2).
  subroutine contact_reactions(st, dt)
    type(state_t), intent(inout) :: st     !! state: walls
    real(wp), intent(in) :: dt             !! the step just taken [s]
    integer :: k
    do k = 1, st%nwall
      st%walls(k)%force = -st%walls(k)%impulse/dt
      st%walls(k)%impulse_acc = st%walls(k)%impulse_acc + st%walls(k)%impulse
      st%walls(k)%work = st%walls(k)%work + dot_product(st%walls(k)%impulse, &
                         wall_velocity(st%walls(k), st%t - 0.5_wp*dt))
    end do
  end subroutine contact_reactions

  !> Steps 2 (USF) and 5 (MUSL): node velocity = momentum / mass on active nodes (zero
  !! elsewhere), then the walls on each active node (no reactions recorded).
  subroutine grid_velocity_walls(st, g, tl, wk, dt)
    type(state_t), intent(in) :: st        !! state (walls, time)
    type(grid_t), intent(inout) :: g       !! grid: velocities
    type(tiles_t), intent(inout) :: tl     !! live spans (span sums untouched)
    type(work_t), intent(inout) :: wk      !! per-wall data of the step
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: k, i0, i1, j0, j1, i, j, n
    real(wp) :: tol
    call wall_setup(st, g, wk, dt, tol)
    !$omp parallel do default(none) schedule(static) shared(st, g, tl, wk, dt, tol) &
    !$omp   private(k, i0, i1, j0, j1, i, j, n) if(wk%par)
    do k = 1, tl%nspan
      call tiles_span(tl, k, i0, i1, j0, j1)
      do j = j0, j1
        do i = i0, i1
          n = 1 + i + g%nx*j
          if (g%mass(n) > g%mass_cut) then
            g%vel(:, n) = g%mom(:, n)/g%mass(n)
            if (st%nwall > 0) call node_walls(st, wk, g, tl, i, j, n, dt, tol, 0)
          else
            g%vel(:, n) = 0.0_wp
          end if
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine grid_velocity_walls

  !> Step 3: momentum update with the nodal force and mass-proportional damping, then the
  !! walls, node by node. vel = new velocity, dvel = its change (with the walls' part, so that
  !! FLIP sees the contact); the momentum the walls add is their impulse on the material.
  subroutine grid_update_walls(prm, st, g, tl, wk, dt)
    type(params_t), intent(in) :: prm      !! parameters (damping, basis)
    type(state_t), intent(inout) :: st     !! state: wall impulses, damped energy
    type(grid_t), intent(inout) :: g       !! grid: velocities, gaps
    type(tiles_t), intent(inout) :: tl     !! live spans, partial sums per span
    type(work_t), intent(inout) :: wk      !! per-wall data, near-wall particle lists
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: k, i0, i1, j0, j1, i, j, n, nact, iw
    real(wp) :: v0(2), v1(2), fac, edamp, damping, tol
    call wall_setup(st, g, wk, dt, tol)
    if (st%nwall > 0) call wall_gaps(prm, st, g, tl, wk)
    fac = 1.0_wp/(1.0_wp + prm%damping*dt)      ! implicit decay of the damping term
    damping = prm%damping
    nact = 0
    !$omp parallel do default(none) schedule(static) &
    !$omp   shared(st, g, tl, wk, dt, fac, damping, tol) &
    !$omp   private(k, i0, i1, j0, j1, i, j, n, v0, v1, edamp) reduction(+: nact) if(wk%par)
    do k = 1, tl%nspan
      call tiles_span(tl, k, i0, i1, j0, j1)
      edamp = 0.0_wp
      tl%span_sum(:, k) = 0.0_wp
      do j = j0, j1
        do i = i0, i1
          n = 1 + i + g%nx*j
          if (.not. g%mass(n) > g%mass_cut) then
            g%vel(:, n) = 0.0_wp
            g%dvel(:, n) = 0.0_wp
            cycle
          end if
          nact = nact + 1
          v0 = g%mom(:, n)/g%mass(n)
          v1 = v0 + dt*g%force(:, n)/g%mass(n)
          if (damping > 0.0_wp) then
            edamp = edamp + 0.5_wp*g%mass(n)*(1.0_wp - fac*fac)*dot_product(v1, v1)
            v1 = fac*v1
          end if
          g%vel(:, n) = v1
          g%dvel(:, n) = v1 - v0
          if (st%nwall > 0) call node_walls(st, wk, g, tl, i, j, n, dt, tol, k)
        end do
      end do
      tl%span_sum(1, k) = edamp
    end do
    !$omp end parallel do
    g%nactive = nact
    st%e_damped = st%e_damped + sum(tl%span_sum(1, 1:tl%nspan))
    do iw = 1, st%nwall                     ! tile order: independent of the thread count
      do k = 1, tl%nspan
        st%walls(iw)%impulse = st%walls(iw)%impulse + tl%span_sum(2*iw:2*iw + 1, k)
      end do
    end do
  end subroutine grid_update_walls

  !> Per wall the velocity over the step, the point and the normal (wk%wall_work), and the
  !! round-off tolerance of the 'slip' planes.
  subroutine wall_setup(st, g, wk, dt, tol)
    type(state_t), intent(in) :: st        !! state (walls, time)
    type(grid_t), intent(in) :: g          !! grid (cell size)
    type(work_t), intent(inout) :: wk      !! per-wall data of the step
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(out) :: tol           !! tolerance on the node distance [m]
    integer :: iw
    if (.not. allocated(wk%wall_work)) allocate(wk%wall_work(6, st%nwall))
    do iw = 1, st%nwall
      wk%wall_work(1:2, iw) = wall_velocity(st%walls(iw), st%t + 0.5_wp*dt)
      wk%wall_work(3:4, iw) = st%walls(iw)%point
      wk%wall_work(5:6, iw) = st%walls(iw)%normal
    end do
    tol = 1.0e-6_wp*g%h
  end subroutine wall_setup

  !> The walls, in order, on active node n = (i, j) (docs/theory.md). With k > 0 (step 3)
  !! the velocity change also enters dvel and the momentum added is summed into the partial
  !! sums of span k. A wall other than 'slip' cannot act where no material is within reach
  !! (gap = huge); a 'slip' wall acts on the nodes on or behind its plane. (Called per node:
  !! scalar derived-type dummies, so that no array descriptor is built per call.)
  subroutine node_walls(st, wk, g, tl, i, j, n, dt, tol, k)
    type(state_t), intent(in) :: st        !! state (walls)
    type(work_t), intent(in) :: wk         !! per wall: velocity, point, normal (wall_work)
    type(grid_t), intent(inout) :: g       !! grid: node velocity (and change) updated
    type(tiles_t), intent(inout) :: tl     !! partial sums per span (written with k > 0)
    integer, intent(in) :: i, j, n         !! node indices and id
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(in) :: tol            !! tolerance on the node distance [m]
    integer, intent(in) :: k               !! span of the node, or 0: no reactions recorded
    integer :: iw
    real(wp) :: xn(2), dist, dp(2)
    xn(1) = g%origin(1) + g%h*real(i, wp)
    xn(2) = g%origin(2) + g%h*real(j, wp)
    do iw = 1, st%nwall
      if (st%walls(iw)%contact == CONTACT_SLIP) then
        dist = dot_product(xn - wk%wall_work(3:4, iw), wk%wall_work(5:6, iw)) - tol
        if (dist > 0.0_wp) cycle
      else
        if (g%gap(iw, n) == huge(1.0_wp)) cycle
        dist = 0.0_wp                         ! (read by 'slip' only)
      end if
      call wall_constrain_node(st%walls(iw)%contact, st%walls(iw)%friction, &
                               wk%wall_work(5:6, iw), wk%wall_work(1:2, iw), dist, &
                               g%gap(iw, n), g%mass(n), dt, g%vel(:, n), dp)
      if (k > 0) then
        g%dvel(:, n) = g%dvel(:, n) + dp/g%mass(n)
        tl%span_sum(2*iw:2*iw + 1, k) = tl%span_sum(2*iw:2*iw + 1, k) + dp
      end if
    end do
  end subroutine node_walls

  !> For every wall but 'slip', the smallest distance to the plane of the material supported
  !! by each node: the lowest corner of each particle's domain (CPDI) or of its extent (linear,
  !! uGIMP); huge where no material is within reach. The particles that may be within reach
  !! are listed per chunk in parallel, then mapped to their nodes in order.
  subroutine wall_gaps(prm, st, g, tl, wk)
    type(params_t), intent(in) :: prm      !! parameters (basis)
    type(state_t), intent(in) :: st        !! state (particles, walls, speed)
    type(grid_t), intent(inout) :: g       !! grid: gaps
    type(tiles_t), intent(in) :: tl        !! live spans
    type(work_t), intent(inout) :: wk      !! near-wall particle lists; basis cache
    integer :: iw, ip, a, b, k, n, nb, nx, ic, nchunk, i0, i1, j0, j1, j, cnt
    real(wp) :: d, reach
    logical :: keep
    if (all(st%walls(:)%contact == CONTACT_SLIP)) return
    nb = wk%nb
    nx = g%nx
    reach = 2.0_wp*g%h + st%dt*(st%vmax + 100.0_wp)   ! particles farther away cannot touch
    nchunk = (st%p%np + chunk - 1)/chunk
    !$omp parallel default(none) shared(st, g, tl, wk, reach, nchunk) &
    !$omp   private(iw, ip, k, i0, i1, j0, j1, j, ic, cnt, keep) if(wk%par)
    !$omp do schedule(static)
    do k = 1, tl%nspan
      call tiles_span(tl, k, i0, i1, j0, j1)
      do j = j0, j1
        do iw = 1, st%nwall
          if (st%walls(iw)%contact /= CONTACT_SLIP) &
            g%gap(iw, 1 + i0 + g%nx*j:1 + i1 + g%nx*j) = huge(1.0_wp)
        end do
      end do
    end do
    !$omp end do nowait
    !$omp do schedule(static)
    do ic = 1, nchunk
      cnt = 0
      do ip = 1 + (ic - 1)*chunk, min(ic*chunk, st%p%np)
        keep = .false.                       ! the first test of material_gap
        do iw = 1, st%nwall
          if (st%walls(iw)%contact == CONTACT_SLIP) cycle
          keep = keep .or. (st%p%x(1, ip) - wk%wall_work(3, iw))*wk%wall_work(5, iw) &
                           + (st%p%x(2, ip) - wk%wall_work(4, iw))*wk%wall_work(6, iw) &
                           <= reach + 4.0_wp*max(st%p%half(1, ip), st%p%half(2, ip))
        end do
        if (keep) then
          wk%near(1 + (ic - 1)*chunk + cnt) = ip
          cnt = cnt + 1
        end if
      end do
      wk%nnear(ic) = cnt
    end do
    !$omp end do
    !$omp end parallel
    do iw = 1, st%nwall
      if (st%walls(iw)%contact == CONTACT_SLIP) cycle
      do ic = 1, nchunk
        do j = 1, wk%nnear(ic)
          ip = wk%near((ic - 1)*chunk + j)
          d = material_gap(prm%basis, st%p, st%walls(iw), ip, reach)
          if (d > reach) cycle
          do b = 0, nb - 1
            do a = 0, nb - 1
              if (wk%w(1 + a + nb*b, ip) == 0.0_wp) cycle
              n = 1 + wk%blk(1, ip) + a + nx*(wk%blk(2, ip) + b)
              g%gap(iw, n) = min(g%gap(iw, n), d)
            end do
          end do
        end do
      end do
    end do
  end subroutine wall_gaps

  !> Distance from wall iw of the lowest point of particle ip's domain (corners for CPDI,
  !! the extent otherwise) [m]; huge when its centre is clearly beyond reach.
  pure function material_gap(basis, p, wall, ip, reach) result(d)
    integer, intent(in) :: basis           !! BASIS_* code
    type(particles_t), intent(in) :: p     !! particles
    type(wall_t), intent(in) :: wall       !! the wall
    integer, intent(in) :: ip              !! particle
    real(wp), intent(in) :: reach          !! largest distance of interest [m]
    real(wp) :: d, nrm(2), pt(2), r1(2), r2(2), xq(2, 4)
    integer :: a
    nrm = wall%normal
    pt = wall%point
    d = dot_product(p%x(:, ip) - pt, nrm)
    if (d > reach + 4.0_wp*maxval(p%half(:, ip))) then
      d = huge(1.0_wp)
      return
    end if
    select case (basis)
    case (BASIS_CPDI2)
      xq = particle_corners(p, ip, BASIS_CPDI2)
      d = huge(1.0_wp)
      do a = 1, 4
        d = min(d, dot_product(xq(:, a) - pt, nrm))
      end do
    case (BASIS_CPDI1)             ! the lowest corner of x -+ r1 -+ r2, in closed form
      r1 = matmul(p%F(:, :, ip), p%r10(:, ip))
      r2 = matmul(p%F(:, :, ip), p%r20(:, ip))
      d = d - abs(dot_product(r1, nrm)) - abs(dot_product(r2, nrm))
    case default                   ! the lowest corner of the square x -+ half
      d = d - p%half(1, ip)*abs(nrm(1)) - p%half(2, ip)*abs(nrm(2))
    end select
  end function material_gap

end module mpm_contact
