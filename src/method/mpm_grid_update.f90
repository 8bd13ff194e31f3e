!> The grid update (steps 2, 3 and 5 of docs/method.md): node velocity = momentum / mass,
!! step 3's momentum update with the nodal force and mass-proportional damping, on the live
!! nodes span by span; each row updated then gets the walls' mirror planes (mpm_contact), and
!! step 3 the walls' surface forces before and their friction after.
! SPDX-License-Identifier: MIT
!
! The damped energy is summed per live span and added in span order, so it does not depend on
! the thread count.
module mpm_grid_update
  use mpm_kinds, only: wp
  use mpm_constants, only: CONTACT_SLIP
  use mpm_grid, only: grid_t
  use mpm_tiles, only: tiles_t, tiles_span
  use mpm_state, only: params_t, state_t, work_t
  use mpm_contact, only: wall_setup, surface_forces, surface_friction_walls, slip_columns, &
                         row_walls
  implicit none
  private
  public :: grid_velocity_walls, grid_update_walls

contains

  !> Steps 2 (USF) and 5 (MUSL): node velocity = momentum / mass on active nodes (zero
  !! elsewhere), then the mirror planes on each active node (no reactions recorded; the
  !! other walls act by forces, in step 3 only).
  subroutine grid_velocity_walls(st, g, tl, wk, dt)
    type(state_t), intent(in) :: st        !! state (walls, time)
    type(grid_t), intent(inout) :: g       !! grid: velocities
    type(tiles_t), intent(inout) :: tl     !! live spans (span sums untouched)
    type(work_t), intent(inout) :: wk      !! per-wall data of the step
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: k, i0, i1, j0, j1, j, n0, f, ib, ia
    real(wp) :: tol
    call wall_setup(st, g, wk, dt, tol)
    !$omp parallel do default(none) schedule(static) shared(st, g, tl, wk, dt, tol) &
    !$omp   private(k, i0, i1, j0, j1, j, n0, f, ib, ia) if(wk%par)
    do k = 1, tl%nspan
      call tiles_span(tl, k, i0, i1, j0, j1)
      call slip_columns(st, wk, g, i0, i1, j0, j1, ib, ia)
      do f = 0, g%nf - 1
        do j = j0, j1
          n0 = g%nx*j + f*g%nn                 ! node (i, j) of field f is n0 + 1 + i
          call velocity_row(i0, i1, n0, size(g%mass), g%mass, g%mom, g%mass_cut, g%vel)
          call row_walls(st, wk, g, tl, i0, i1, ib, ia, j, n0, tol, 0, 0.0_wp)
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine grid_velocity_walls

  !> Step 3: momentum update with the nodal force, the walls' surface forces and mass-
  !! proportional damping, then the mirror planes node by node and the walls' friction.
  !! vel = new velocity, dvel = its change (with the walls' part, so that FLIP sees the
  !! contact); the momentum the walls add is their impulse on the material.
  subroutine grid_update_walls(prm, st, g, tl, wk, dt)
    type(params_t), intent(in) :: prm      !! parameters (damping, basis, wave speed)
    type(state_t), intent(inout) :: st     !! state: wall impulses
    type(grid_t), intent(inout) :: g       !! grid: forces, velocities
    type(tiles_t), intent(inout) :: tl     !! live spans, partial sums per span
    type(work_t), intent(inout) :: wk      !! per-wall data, surface points
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: k, i0, i1, j0, j1, j, n0, nact, iw, f, ib, ia
    real(wp) :: fac, damping, tol, flip
    call wall_setup(st, g, wk, dt, tol)
    call surface_forces(prm, st, g, wk, dt)
    flip = prm%flip
    fac = 1.0_wp/(1.0_wp + prm%damping*dt)      ! implicit decay of the damping term
    damping = prm%damping
    call damping_allocate(damping, size(g%mass), wk)
    nact = 0
    !$omp parallel do default(none) schedule(static) &
    !$omp   shared(st, g, tl, wk, dt, fac, damping, tol, flip) &
    !$omp   private(k, i0, i1, j0, j1, j, n0, f, ib, ia) reduction(+: nact) &
    !$omp   if(wk%par)
    do k = 1, tl%nspan
      call tiles_span(tl, k, i0, i1, j0, j1)
      call slip_columns(st, wk, g, i0, i1, j0, j1, ib, ia)
      tl%span_sum(:, k) = 0.0_wp
      do f = 0, g%nf - 1
        do j = j0, j1
          n0 = g%nx*j + f*g%nn                 ! node (i, j) of field f is n0 + 1 + i
          call update_row(i0, i1, n0, size(g%mass), g%mass, g%mom, g%force, g%mass_cut, dt, &
                          damping, fac, g%vel, g%dvel, wk%vdamp, nact)
          call row_walls(st, wk, g, tl, i0, i1, ib, ia, j, n0, tol, k, flip)
        end do
      end do
    end do
    !$omp end parallel do
    g%nactive = nact
    do iw = 1, st%nwall                     ! tile order: independent of the thread count
      if (st%walls(iw)%contact /= CONTACT_SLIP) cycle
      do k = 1, tl%nspan
        st%walls(iw)%impulse = st%walls(iw)%impulse + tl%span_sum(2*iw:2*iw + 1, k)
      end do
    end do
    call surface_friction_walls(st, g, wk, tol)
  end subroutine grid_update_walls

  !> The damping's node velocity changes (wk%vdamp): one per node with damping, none without.
  subroutine damping_allocate(damping, nt, wk)
    real(wp), intent(in) :: damping        !! mass-proportional damping [1/s]
    integer, intent(in) :: nt              !! nodes of all fields
    type(work_t), intent(inout) :: wk      !! vdamp allocated
    integer :: n
    n = 0
    if (damping > 0.0_wp) n = nt
    if (allocated(wk%vdamp)) then
      if (size(wk%vdamp, 2) == n) return
      deallocate(wk%vdamp)
    end if
    allocate(wk%vdamp(2, n))
  end subroutine damping_allocate

  !> Node velocities of one span row (nodes n0 + 1 + i, i = i0..i1): momentum / mass on the
  !! active nodes, zero on the others (steps 2 and 5). Plain arrays: the loop keeps its
  !! scalars in registers.
  pure subroutine velocity_row(i0, i1, n0, nt, mass, mom, mass_cut, vel)
    integer, intent(in) :: i0, i1          !! columns of the row
    integer, intent(in) :: n0              !! node of column i is n0 + 1 + i
    integer, intent(in) :: nt              !! nodes of all fields
    real(wp), intent(in) :: mass(nt)       !! node mass [kg/m]
    real(wp), intent(in) :: mom(2, nt)     !! node momentum [kg/s]
    real(wp), intent(in) :: mass_cut       !! active-node cut-off [kg/m]
    real(wp), intent(inout) :: vel(2, nt)  !! node velocity [m/s]
    integer :: n
    do n = n0 + 1 + i0, n0 + 1 + i1
      if (mass(n) > mass_cut) then
        vel(:, n) = mom(:, n)/mass(n)
      else
        vel(1, n) = 0.0_wp
        vel(2, n) = 0.0_wp
      end if
    end do
  end subroutine velocity_row

  !> Step 3 on one span row (nodes n0 + 1 + i, i = i0..i1): the momentum update with the
  !! nodal force and the damping on the active nodes (their count into nact; the damping's
  !! velocity change into vdamp, whose energy G2P counts at the particles), vel and dvel zero
  !! on the others.
  pure subroutine update_row(i0, i1, n0, nt, mass, mom, force, mass_cut, dt, damping, fac, &
                             vel, dvel, vdamp, nact)
    integer, intent(in) :: i0, i1          !! columns of the row
    integer, intent(in) :: n0              !! node of column i is n0 + 1 + i
    integer, intent(in) :: nt              !! nodes of all fields
    real(wp), intent(in) :: mass(nt)       !! node mass [kg/m]
    real(wp), intent(in) :: mom(2, nt)     !! node momentum [kg/s]
    real(wp), intent(in) :: force(2, nt)   !! node force [N/m]
    real(wp), intent(in) :: mass_cut       !! active-node cut-off [kg/m]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(in) :: damping        !! mass-proportional damping [1/s]
    real(wp), intent(in) :: fac            !! its decay over the step [-]
    real(wp), intent(inout) :: vel(2, nt)  !! node velocity [m/s]
    real(wp), intent(inout) :: dvel(2, nt) !! its change over the step [m/s]
    real(wp), intent(inout) :: vdamp(:,:)  !! the damping's part of it (2, nt; damping > 0)
                                           !! [m/s]
    integer, intent(inout) :: nact         !! active nodes
    integer :: n
    real(wp) :: v0(2), v1(2)
    do n = n0 + 1 + i0, n0 + 1 + i1
      if (.not. mass(n) > mass_cut) then
        vel(1, n) = 0.0_wp                   ! (element by element: no memset call)
        vel(2, n) = 0.0_wp
        dvel(1, n) = 0.0_wp
        dvel(2, n) = 0.0_wp
        if (damping > 0.0_wp) vdamp(:, n) = 0.0_wp
        cycle
      end if
      nact = nact + 1
      v0 = mom(:, n)/mass(n)
      v1 = v0 + dt*force(:, n)/mass(n)
      if (damping > 0.0_wp) then
        vdamp(:, n) = (fac - 1.0_wp)*v1
        v1 = fac*v1
      end if
      vel(:, n) = v1
      dvel(:, n) = v1 - v0
    end do
  end subroutine update_row

end module mpm_grid_update
