!> Wall contact on the grid (steps 3 and 5 of docs/method.md): the walls other than 'slip'
!! act at the material surface (mpm_surface_contact: penalty forces on the surface points,
!! friction as a bounded tangential impulse); the 'slip' mirror planes act on the nodes on or
!! behind them; the reactions (impulse, force, work) of the walls and the energy stored in
!! the contact. mpm_walls keeps the wall type and its prescribed motion.
! SPDX-License-Identifier: MIT
!
! The node velocity update (momentum and force over mass, damping) runs in the same pass over
! the live nodes as the mirror planes: mpm_grid_update's loops call row_walls here on each
! row they update (grid_velocity_walls, the USF velocity and the MUSL re-map: no reactions;
! grid_update_walls, step 3: the momentum the walls add is their impulse). Node sums
! (impulses) are formed per live span and added in span order, so they do not depend on the
! thread count; the surface points are gathered and pushed in corner (or particle) order.
module mpm_contact
  use mpm_kinds, only: wp
  use mpm_constants, only: CONTACT_SLIP, CONTACT_BONDED, EXIT_NUMERIC
  use mpm_grid, only: grid_t
  use mpm_tiles, only: tiles_t
  use mpm_walls, only: wall_t, wall_velocity, wall_mirror_node, wall_travel, wall_free_step, &
                       wall_shift
  use mpm_surface_contact, only: surface_points, surface_push, surface_friction, surface_energy, &
                                 surface_slip_loss, contact_alpha, surface_tie, &
                                 surface_step_energy
  use mpm_surface_curve, only: surface_curve_points
  use mpm_body_tie, only: body_tie_forces, body_tie_energy, body_tie_step_energy
  use mpm_constants, only: BASIS_CPDI2
  use mpm_state, only: params_t, state_t, work_t
  use mpm_strings, only: itoa, rtoa
  implicit none
  private
  public :: contact_begin_step, contact_reactions, contact_energy, contact_check, &
            slip_span_columns, contact_tie, contact_step_energy
  ! for the node loops of mpm_grid_update
  public :: wall_setup, surface_forces, surface_friction_walls, slip_columns, row_walls

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
  !! its impulse summed for the history, its work impulse . v_wall(t - dt/2); a wall with mass
  !! moves under the impulse's reaction and gravity (wall_free_step).
  subroutine contact_reactions(st, dt, gravity)
    type(state_t), intent(inout) :: st     !! state: walls
    real(wp), intent(in) :: dt             !! the step just taken [s]
    real(wp), intent(in) :: gravity(2)     !! gravity [m/s^2]
    integer :: k
    do k = 1, st%nwall
      st%walls(k)%force = -st%walls(k)%impulse/dt
      st%walls(k)%impulse_acc = st%walls(k)%impulse_acc + st%walls(k)%impulse
      if (st%walls(k)%mass > 0.0_wp) then
        call wall_free_step(st%walls(k), gravity, dt)
      else
        st%walls(k)%work = st%walls(k)%work + dot_product(st%walls(k)%impulse, &
                           wall_velocity(st%walls(k), st%t - 0.5_wp*dt))
      end if
    end do
  end subroutine contact_reactions

  !> The penalty forces of every wall but 'slip' on the surface points behind it at the start
  !! of the step, added to the node forces; their momentum over dt is the wall's impulse. (The
  !! energy stored in them is counted after the step, contact_step_energy.)
  subroutine surface_forces(prm, st, g, wk, dt)
    type(params_t), intent(in) :: prm      !! parameters (basis, wave speed)
    type(state_t), intent(inout) :: st     !! state: particles, wall impulses
    type(grid_t), intent(inout) :: g       !! grid: forces
    type(work_t), intent(inout) :: wk      !! per-wall data, surface points
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: iw, nm
    real(wp) :: imp(2), mirror(4, st%nwall), e_tie
    call surface_allocate(st, wk)
    do iw = 1, st%nwall
      if (st%walls(iw)%contact == CONTACT_SLIP) cycle
      wk%surf(iw)%shift = wall_shift(st%walls(iw), st%t)   ! the anchors of a 'bonded' wall
      if (prm%basis == BASIS_CPDI2 .and. prm%surface_curve) then
        call mirror_planes(st, mirror, nm)
        call surface_curve_points(st%p, wk%wall_work(3:4, iw), wk%wall_work(5:6, iw), &
                                  wall_stiffness(prm, g, st%walls(iw)), mirror(:, 1:nm), &
                                  1.0e-6_wp*g%h, wk%surf(iw))
      else
        call surface_points(st%p, prm%basis, wk%wall_work(3:4, iw), wk%wall_work(5:6, iw), &
                            wall_stiffness(prm, g, st%walls(iw)), wk%par, wk%surf(iw))
      end if
      call surface_push(wk%surf(iw), g%origin, g%h, g%nx, g%ny, g%mass, g%mass_cut, wk%nb, &
                        wk%blk, wk%w, wk%gw, wk%wall_work(5:6, iw), dt, g%force, imp, g%nf, &
                        prm%field, prm%corner_field)
      st%walls(iw)%impulse = st%walls(iw)%impulse + imp
    end do
    if (prm%ties%n == 0) return              ! 'bonded' bodies: their ties (mpm_body_tie)
    if (.not. allocated(wk%tie_imp)) allocate(wk%tie_imp(3, prm%npair))
    if (.not. allocated(wk%tie_d)) allocate(wk%tie_d(2, prm%ties%n))
    wk%tie_imp = 0.0_wp
    call body_tie_forces(prm%ties, st%p%xc, prm%corner_field, g, stiffness(prm, g), dt, e_tie, &
                         wk%tie_imp, wk%tie_d)
  end subroutine surface_forces

  !> Friction of the walls with 'coulomb' or 'stick' on the points they push (velocities after
  !! the update), then the 'slip' planes again on the nodes of those points: a platen's
  !! friction must not move a node off a mirror plane.
  subroutine surface_friction_walls(st, g, wk, tol)
    type(state_t), intent(inout) :: st     !! state: wall impulses
    type(grid_t), intent(inout) :: g       !! grid: velocities and their changes
    type(work_t), intent(inout) :: wk      !! per-wall data, surface points
    real(wp), intent(in) :: tol            !! tolerance on the node distance [m]
    integer :: iw, jw, c, a, n, i, j
    real(wp) :: imp(2), xn(2), dist, dp(2)
    do iw = 1, st%nwall
      if (st%walls(iw)%contact == CONTACT_SLIP) cycle
      if (wk%surf(iw)%npt == 0) cycle
      call surface_friction(wk%surf(iw), st%walls(iw)%contact, st%walls(iw)%friction, &
                            wk%wall_work(5:6, iw), wk%wall_work(1:2, iw), g%vel, g%dvel, imp)
      if (wk%surf(iw)%sweeps == 0) cycle
      st%walls(iw)%impulse = st%walls(iw)%impulse + imp
      do jw = 1, st%nwall
        if (st%walls(jw)%contact /= CONTACT_SLIP) cycle
        do c = 1, wk%surf(iw)%npt
          do a = 1, wk%surf(iw)%nnode
            if (wk%surf(iw)%nw(a, c) == 0.0_wp) cycle
            n = wk%surf(iw)%node(a, c)
            i = mod(mod(n - 1, g%nn), g%nx)     ! the node of any field
            j = mod(n - 1, g%nn)/g%nx
            xn = g%origin + g%h*[real(i, wp), real(j, wp)]
            dist = dot_product(xn - wk%wall_work(3:4, jw), wk%wall_work(5:6, jw)) - tol
            if (dist > 0.0_wp) cycle
            call wall_mirror_node(wk%wall_work(5:6, jw), wk%wall_work(1:2, jw), dist, &
                                  g%mass(n), g%vel(:, n), dp)
            g%dvel(:, n) = g%dvel(:, n) + dp/g%mass(n)
            st%walls(jw)%impulse = st%walls(jw)%impulse + dp
          end do
        end do
      end do
      ! the friction's loss: its impulses times the slip they leave (wall less point
      ! velocity after the solve and the mirror planes; docs/method.md, "Energies")
      st%e_contact_loss = st%e_contact_loss + &
        surface_slip_loss(wk%surf(iw), wk%wall_work(5:6, iw), wk%wall_work(1:2, iw), g%vel)
    end do
  end subroutine surface_friction_walls

  !> End of a step: the energy stored in the walls' contact as the step conserves it, into
  !! st%e_contact [J/m]: per CPDI2 point of the step's forces, 1/2 k_c times its gap at the
  !! start (that of its force) times its gap at the end; the corners of the other bases,
  !! 1/2 k_c g_c^2 at the start (mpm_surface_contact, surface_step_energy).
  !! A point behind a wall only at the end has no energy yet: its force, and the wall's work
  !! through it, come in the next step (counted with the end's gap alone, a wall meeting a
  !! body at rest would show energy before any work, which the growth check of a body with E0
  !! = 0 takes for an instability). vel: the node velocity the points moved with. The ties of
  !! 'bonded' bodies likewise: 1/2 k d . d' (mpm_body_tie, body_tie_step_energy).
  subroutine contact_step_energy(prm, st, g, wk, dt)
    type(params_t), intent(in) :: prm      !! parameters (ties, stiffness)
    type(state_t), intent(inout) :: st     !! state: e_contact
    type(grid_t), intent(in) :: g          !! grid: node velocities of the step
    type(work_t), intent(in) :: wk         !! surface points and walls of the step
    real(wp), intent(in) :: dt             !! the step just taken [s]
    integer :: iw
    st%e_contact = 0.0_wp
    do iw = 1, st%nwall
      if (.not. allocated(wk%surf)) exit
      if (st%walls(iw)%contact == CONTACT_SLIP) cycle
      st%e_contact = st%e_contact + surface_step_energy(wk%surf(iw), wk%wall_work(5:6, iw), &
                                                        wk%wall_work(1:2, iw), g%vel, dt)
    end do
    if (prm%ties%n > 0 .and. allocated(wk%tie_d)) st%e_contact = st%e_contact + &
      body_tie_step_energy(prm%ties, st%p%xc, stiffness(prm, g), wk%tie_d)
  end subroutine contact_step_energy

  !> The energy stored in the walls' contact now (time st%t, particles at the end of the
  !! step), into st%e_contact [J/m].
  subroutine contact_energy(prm, st, g, wk)
    type(params_t), intent(in) :: prm      !! parameters (basis, wave speed)
    type(state_t), intent(inout) :: st     !! state: e_contact
    type(grid_t), intent(in) :: g          !! grid (cell size)
    type(work_t), intent(inout) :: wk      !! surface points (overwritten)
    integer :: iw, nm
    real(wp) :: xw(2), mirror(4, st%nwall)
    st%e_contact = 0.0_wp
    call surface_allocate(st, wk)
    do iw = 1, st%nwall
      if (st%walls(iw)%contact == CONTACT_SLIP) cycle
      xw = st%walls(iw)%point0 - wall_travel(st%walls(iw), st%t)*st%walls(iw)%normal
      wk%surf(iw)%shift = wall_shift(st%walls(iw), st%t)
      if (prm%basis == BASIS_CPDI2 .and. prm%surface_curve) then
        call mirror_planes(st, mirror, nm)
        call surface_curve_points(st%p, xw, st%walls(iw)%normal, &
                                  wall_stiffness(prm, g, st%walls(iw)), mirror(:, 1:nm), &
                                  1.0e-6_wp*g%h, wk%surf(iw))
      else
        call surface_points(st%p, prm%basis, xw, st%walls(iw)%normal, &
                            wall_stiffness(prm, g, st%walls(iw)), wk%par, wk%surf(iw))
      end if
      st%e_contact = st%e_contact + surface_energy(wk%surf(iw))
    end do
    if (prm%ties%n > 0) st%e_contact = st%e_contact + body_tie_energy(prm%ties, st%p%xc, &
                                                                      stiffness(prm, g))
  end subroutine contact_energy

  !> At t = 0: the surface points tied to each 'bonded' wall, those less than h/2 in front of
  !! it (mpm_surface_contact, surface_tie), kept in wk%surf for the whole run.
  subroutine contact_tie(prm, st, h, wk)
    type(params_t), intent(in) :: prm      !! parameters (basis)
    type(state_t), intent(in) :: st        !! state at t = 0 (particles, walls)
    real(wp), intent(in) :: h              !! cell size [m]
    type(work_t), intent(inout) :: wk      !! surf allocated; the ties set
    integer :: iw
    call surface_allocate(st, wk)
    do iw = 1, st%nwall
      if (st%walls(iw)%contact /= CONTACT_BONDED) cycle
      call surface_tie(st%p, prm%basis, st%walls(iw)%point0, st%walls(iw)%normal, 0.5_wp*h, &
                       wk%surf(iw))
    end do
  end subroutine contact_tie

  !> The 'slip' mirror planes now: a point and the unit normal of each (4, nm) [m, -].
  subroutine mirror_planes(st, mirror, nm)
    type(state_t), intent(in) :: st        !! state (walls, time)
    real(wp), intent(out) :: mirror(:,:)   !! point and normal of each (4, >= nm)
    integer, intent(out) :: nm             !! mirror planes
    integer :: jw
    nm = 0
    do jw = 1, st%nwall
      if (st%walls(jw)%contact /= CONTACT_SLIP) cycle
      nm = nm + 1
      mirror(1:2, nm) = st%walls(jw)%point0 - wall_travel(st%walls(jw), st%t)*st%walls(jw)%normal
      mirror(3:4, nm) = st%walls(jw)%normal
    end do
  end subroutine mirror_planes

  !> Penalty stiffness per unit mass of a surface point, alpha (c / h)^2 [1/s^2]
  !! (mpm_surface_contact).
  pure function stiffness(prm, g) result(kf)
    type(params_t), intent(in) :: prm      !! parameters (wave speed)
    type(grid_t), intent(in) :: g          !! grid (cell size)
    real(wp) :: kf
    kf = contact_alpha*(prm%c_max/g%h)**2
  end function stiffness

  !> The penalty stiffness per unit mass of wall w's surface points: its &wall penalty times
  !! the default (stiffness) [1/s^2].
  pure function wall_stiffness(prm, g, w) result(kf)
    type(params_t), intent(in) :: prm      !! parameters (wave speed)
    type(grid_t), intent(in) :: g          !! grid (cell size)
    type(wall_t), intent(in) :: w          !! the wall
    real(wp) :: kf
    kf = w%penalty*stiffness(prm, g)
  end function wall_stiffness

  !> After step 3: a wall whose surface points lie more than half a cell behind it moves
  !! faster than its contact can push the material away (the penalty acts within about h / c):
  !! stat = EXIT_NUMERIC with a message, before the energies overflow.
  subroutine contact_check(st, wk, h, stat, errmsg)
    type(state_t), intent(in) :: st        !! state (walls)
    type(work_t), intent(in) :: wk         !! surface points of the step
    real(wp), intent(in) :: h              !! cell size [m]
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(inout) :: errmsg  !! what failed (set on failure)
    integer :: iw
    stat = 0
    if (.not. allocated(wk%surf)) return
    do iw = 1, st%nwall
      if (st%walls(iw)%contact == CONTACT_SLIP) cycle
      if (wk%surf(iw)%gmin >= -0.5_wp*h) cycle
      stat = EXIT_NUMERIC
      errmsg = 'wall '//itoa(iw)//': the material lies '//rtoa(-wk%surf(iw)%gmin)// &
        ' m behind the wall (more than half a cell, h = '//rtoa(h)//' m) at t = '// &
        rtoa(st%t)//' s: the wall moves into the material faster than its contact can push '// &
        'the material away (it acts within about h / c; docs/method.md). Lower the wall''s '// &
        'speed, or cfl if the material itself moves that fast'
      return
    end do
  end subroutine contact_check

  !> One set of surface points per wall.
  subroutine surface_allocate(st, wk)
    type(state_t), intent(in) :: st        !! state (walls)
    type(work_t), intent(inout) :: wk      !! surf allocated
    if (allocated(wk%surf)) then
      if (size(wk%surf) == st%nwall) return
      deallocate(wk%surf)
    end if
    allocate(wk%surf(st%nwall))
  end subroutine surface_allocate

  !> Per wall the velocity over the step, the point, the normal and the velocity over the step
  !! before (t - dt/2; zero before t = 0) (wk%wall_work), and the round-off tolerance of the
  !! 'slip' planes.
  subroutine wall_setup(st, g, wk, dt, tol)
    type(state_t), intent(in) :: st        !! state (walls, time)
    type(grid_t), intent(in) :: g          !! grid (cell size)
    type(work_t), intent(inout) :: wk      !! per-wall data of the step
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(out) :: tol           !! tolerance on the node distance [m]
    integer :: iw
    if (.not. allocated(wk%wall_work)) allocate(wk%wall_work(8, st%nwall))
    do iw = 1, st%nwall
      wk%wall_work(1:2, iw) = wall_velocity(st%walls(iw), st%t + 0.5_wp*dt)
      wk%wall_work(7:8, iw) = 0.0_wp
      if (st%t - 0.5_wp*dt > 0.0_wp) wk%wall_work(7:8, iw) = wall_velocity(st%walls(iw), &
                                                                           st%t - 0.5_wp*dt)
      wk%wall_work(3:4, iw) = st%walls(iw)%point
      wk%wall_work(5:6, iw) = st%walls(iw)%normal
    end do
    tol = 1.0e-6_wp*g%h
  end subroutine wall_setup

  !> The node columns of the span (nodes i0..i1 by j0..j1) on which a 'slip' plane can act:
  !! i <= ib or i >= ia (none: ib < i0 and ia > i1), over the slip walls (slip_span_columns).
  pure subroutine slip_columns(st, wk, g, i0, i1, j0, j1, ib, ia)
    type(state_t), intent(in) :: st        !! state (walls)
    type(work_t), intent(in) :: wk         !! per wall: point, normal (wall_work)
    type(grid_t), intent(in) :: g          !! grid (origin, cell size)
    integer, intent(in) :: i0, i1, j0, j1  !! node columns and rows of the span
    integer, intent(out) :: ib, ia         !! columns i <= ib and i >= ia may be acted on
    integer :: iw
    ib = i0 - 1
    ia = i1 + 1
    do iw = 1, st%nwall
      if (st%walls(iw)%contact /= CONTACT_SLIP) cycle
      call slip_span_columns(g%origin, g%h, i0, i1, j0, j1, wk%wall_work(3:4, iw), &
                             wk%wall_work(5:6, iw), ib, ia)
    end do
  end subroutine slip_columns

  !> Widen the columns i <= ib and i >= ia of a span (nodes i0..i1 by j0..j1 of the grid with
  !! node (0, 0) at `origin`) to every column on which the plane through pw with unit normal nw
  !! can act (node_walls: a node at most tol, a millionth of a cell, in front of it). The
  !! distance to the plane is linear over the span, so a span whose four corners all lie more
  !! than a cell in front of it has none; otherwise the columns whose two end nodes lie more
  !! than a cell in front are left out (the nearer end's distance plus the column slope
  !! h n_x, with a column more; the cell of margin covers every rounding). A normal along the
  !! columns (n_x = 0) or NaN distances: every column.
  pure subroutine slip_span_columns(origin, h, i0, i1, j0, j1, pw, nw, ib, ia)
    real(wp), intent(in) :: origin(2)      !! position of node (0, 0) [m]
    real(wp), intent(in) :: h              !! cell size [m]
    integer, intent(in) :: i0, i1, j0, j1  !! node columns and rows of the span
    real(wp), intent(in) :: pw(2), nw(2)   !! a point of the plane [m], its unit normal [-]
    integer, intent(inout) :: ib, ia       !! columns i <= ib and i >= ia may be acted on
    real(wp) :: xlo(2), xhi(2), d(4), slope, b
    xlo = origin + h*real([i0, j0], wp)
    xhi = origin + h*real([i1, j1], wp)
    d(1) = (xlo(1) - pw(1))*nw(1) + (xlo(2) - pw(2))*nw(2)
    d(2) = (xhi(1) - pw(1))*nw(1) + (xlo(2) - pw(2))*nw(2)
    d(3) = (xlo(1) - pw(1))*nw(1) + (xhi(2) - pw(2))*nw(2)
    d(4) = (xhi(1) - pw(1))*nw(1) + (xhi(2) - pw(2))*nw(2)
    slope = h*nw(1)                        ! distance per column
    if (all(d > h)) return                 ! (NaN: on, as node_walls would test)
    if (slope > 0.0_wp) then               ! nearest at i0: columns up to i0 + b + 1
      b = (h - min(d(1), d(3)))/slope
      if (b < real(i1 - i0, wp)) then
        ib = max(ib, i0 + int(max(b, 0.0_wp)) + 1)
      else
        ib = i1
      end if
    else if (slope < 0.0_wp) then          ! nearest at i1: columns from i1 - b - 1
      b = (h - min(d(2), d(4)))/(-slope)
      if (b < real(i1 - i0, wp)) then
        ia = min(ia, i1 - int(max(b, 0.0_wp)) - 1)
      else
        ia = i0
      end if
    else                                   ! parallel to the columns, or NaN: every column
      ib = i1
    end if
  end subroutine slip_span_columns

  !> The 'slip' mirror planes on the active nodes of a span row (node (i, j) is n0 + 1 + i,
  !! i = i0..i1) in the columns they can reach (i <= ib or i >= ia, slip_columns), in order.
  subroutine row_walls(st, wk, g, tl, i0, i1, ib, ia, j, n0, tol, k, flip)
    type(state_t), intent(in) :: st        !! state (walls)
    type(work_t), intent(in) :: wk         !! per wall: velocity, point, normal (wall_work)
    type(grid_t), intent(inout) :: g       !! grid: node velocity (and change) updated
    type(tiles_t), intent(inout) :: tl     !! partial sums per span (written with k > 0)
    integer, intent(in) :: i0, i1, ib, ia  !! columns of the row; those the planes can reach
    integer, intent(in) :: j, n0           !! row; node of column i is n0 + 1 + i
    real(wp), intent(in) :: tol            !! tolerance on the node distance [m]
    integer, intent(in) :: k               !! span of the row, or 0: no reactions recorded
    real(wp), intent(in) :: flip           !! FLIP fraction (step 3) [-]
    integer :: i
    do i = i0, min(ib, i1)
      if (g%mass(n0 + 1 + i) > g%mass_cut) call node_walls(st, wk, g, tl, i, j, n0 + 1 + i, &
                                                           tol, k, flip)
    end do
    do i = max(ia, ib + 1, i0), i1
      if (g%mass(n0 + 1 + i) > g%mass_cut) call node_walls(st, wk, g, tl, i, j, n0 + 1 + i, &
                                                           tol, k, flip)
    end do
  end subroutine row_walls

  !> The 'slip' mirror planes, in order, on active node n = (i, j): a node on or behind the
  !! plane moves with it along the normal. With k > 0 (step 3) the FLIP increment dvel is the
  !! change of the constrained velocity: the start-of-step velocity mom/m is mirrored too
  !! (its normal part, relative to the plane's velocity over the step before, is removed).
  !! On a symmetry plane, mom/m holds the normal momentum of one side only, which the full
  !! model's mirror image cancels; taken as a velocity change, it pulled the normal velocity
  !! of the particles next to the plane towards zero at every step (a PIC-like damping: an
  !! elastic half ring lost 0.7 % of its energy in a millisecond of free vibration, the full
  !! ring 0.1 %; docs/method.md). The momentum added, including FLIP's share of that
  !! correction, is summed into the partial sums of span k: the impulse is exactly the
  !! momentum the particles receive. (Called per node: scalar derived-type dummies, so that no
  !! array descriptor is built per call.)
  subroutine node_walls(st, wk, g, tl, i, j, n, tol, k, flip)
    type(state_t), intent(in) :: st        !! state (walls)
    type(work_t), intent(in) :: wk         !! per wall: velocity, point, normal (wall_work)
    type(grid_t), intent(inout) :: g       !! grid: node velocity (and change) updated
    type(tiles_t), intent(inout) :: tl     !! partial sums per span (written with k > 0)
    integer, intent(in) :: i, j, n         !! node indices and id
    real(wp), intent(in) :: tol            !! tolerance on the node distance [m]
    integer, intent(in) :: k               !! span of the node, or 0: no reactions recorded
    real(wp), intent(in) :: flip           !! FLIP fraction (step 3) [-]
    integer :: iw
    real(wp) :: xn(2), dist, dp(2), v0(2), v0n
    v0 = g%mom(:, n)/g%mass(n)
    xn(1) = g%origin(1) + g%h*real(i, wp)
    xn(2) = g%origin(2) + g%h*real(j, wp)
    do iw = 1, st%nwall
      if (st%walls(iw)%contact /= CONTACT_SLIP) cycle
      dist = dot_product(xn - wk%wall_work(3:4, iw), wk%wall_work(5:6, iw)) - tol
      if (dist > 0.0_wp) cycle
      call wall_mirror_node(wk%wall_work(5:6, iw), wk%wall_work(1:2, iw), dist, g%mass(n), &
                            g%vel(:, n), dp)
      if (k > 0) then
        v0n = dot_product(v0 - wk%wall_work(7:8, iw), wk%wall_work(5:6, iw))
        v0 = v0 - v0n*wk%wall_work(5:6, iw)
        g%dvel(:, n) = g%dvel(:, n) + dp/g%mass(n) + v0n*wk%wall_work(5:6, iw)
        tl%span_sum(2*iw:2*iw + 1, k) = tl%span_sum(2*iw:2*iw + 1, k) + dp &
          + (flip*g%mass(n)*v0n)*wk%wall_work(5:6, iw)
      end if
    end do
  end subroutine node_walls

end module mpm_contact
