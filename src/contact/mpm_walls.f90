!> Rigid straight walls (platens, targets, mirror planes): the wall type, its prescribed motion,
!! the mirror-plane rule on a node, and its checkpoint record (docs/method.md).
! SPDX-License-Identifier: MIT
!
! A 'slip' mirror plane acts on the grid nodes on or behind it (the grid has nodes on every
! mirror plane); the other walls act at the material surface (mpm_surface_contact, called from
! mpm_contact). The momentum a wall adds, divided by dt, is its force.
module mpm_walls
  use mpm_kinds, only: wp
  use mpm_constants, only: pi, max_table, CONTACT_FRICTIONLESS
  implicit none
  private
  public :: wall_t, wall_factor, wall_travel, wall_velocity, wall_mirror_node, &
            walls_write_state, walls_read_state

  !> A rigid plane with prescribed motion.
  type :: wall_t
    real(wp) :: point0(2) = 0.0_wp        !! point on the plane at t = 0 [m]
    real(wp) :: normal(2) = [0.0_wp, 1.0_wp]  !! unit normal into the material side [-]
    integer :: contact = CONTACT_FRICTIONLESS  !! CONTACT_* code
    real(wp) :: friction = 0.0_wp         !! Coulomb coefficient [-]
    real(wp) :: velocity(2) = 0.0_wp      !! prescribed velocity (full value) [m/s]
    real(wp) :: ramp = 0.0_wp             !! smooth rise time [s]
    integer :: n_motion = 0               !! table points (0 = ramp law)
    real(wp) :: motion_t(max_table) = 0.0_wp  !! table times [s]
    real(wp) :: motion_f(max_table) = 0.0_wp  !! table factors [-]
    logical :: mirror = .false.           !! added by a body sector
    ! state, updated every step
    real(wp) :: point(2) = 0.0_wp         !! current point on the plane [m]
    real(wp) :: impulse(2) = 0.0_wp       !! impulse on the material this step [N s per depth]
    real(wp) :: force(2) = 0.0_wp         !! force of the material on the wall, last step [N/m]
    real(wp) :: impulse_acc(2) = 0.0_wp   !! impulse on the material since the last history row
    real(wp) :: work = 0.0_wp             !! work done on the material so far [J/m]
  end type wall_t

contains

  !> Factor on the prescribed velocity at time t: smooth ramp (1 - cos)/2, or the table.
  pure function wall_factor(w, t) result(f)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: f
    integer :: k
    if (w%n_motion > 0) then
      if (t <= w%motion_t(1)) then
        f = w%motion_f(1)
      else if (t >= w%motion_t(w%n_motion)) then
        f = w%motion_f(w%n_motion)
      else
        do k = 1, w%n_motion - 1
          if (t < w%motion_t(k + 1)) exit
        end do
        f = w%motion_f(k) + (w%motion_f(k + 1) - w%motion_f(k))*(t - w%motion_t(k)) &
            /(w%motion_t(k + 1) - w%motion_t(k))
      end if
    else if (w%ramp > 0.0_wp .and. t < w%ramp) then
      f = 0.5_wp*(1.0_wp - cos(pi*t/w%ramp))
    else
      f = 1.0_wp
    end if
  end function wall_factor

  !> Integral of the velocity factor from 0 to t [s] (exact for the ramp and the table).
  pure function factor_integral(w, t) result(s)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: s, ta, tb
    integer :: k
    if (w%n_motion > 0) then
      s = w%motion_f(1)*min(t, w%motion_t(1))
      do k = 1, w%n_motion - 1
        ta = w%motion_t(k)
        if (t <= ta) exit
        tb = min(t, w%motion_t(k + 1))
        s = s + (tb - ta)*(w%motion_f(k) + 0.5_wp*(w%motion_f(k + 1) - w%motion_f(k)) &
                 *(tb - ta)/(w%motion_t(k + 1) - ta))
      end do
      if (t > w%motion_t(w%n_motion)) s = s + w%motion_f(w%n_motion)*(t - w%motion_t(w%n_motion))
    else if (w%ramp > 0.0_wp) then
      ta = min(t, w%ramp)
      s = 0.5_wp*(ta - w%ramp/pi*sin(pi*ta/w%ramp)) + max(t - w%ramp, 0.0_wp)
    else
      s = t
    end if
  end function factor_integral

  !> Prescribed wall velocity at time t [m/s].
  pure function wall_velocity(w, t) result(v)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: v(2)
    v = w%velocity*wall_factor(w, t)
  end function wall_velocity

  !> Point on the plane at time t [m] is point0 + velocity * integral of the factor; this
  !! returns the travel along minus the normal since t = 0 [m] and sets nothing.
  pure function wall_travel(w, t) result(d)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: d
    d = -dot_product(w%velocity, w%normal)*factor_integral(w, t)
  end function wall_travel

  !> A 'slip' mirror plane on one node: a node on or behind the plane (xnode_dist <= 0) moves
  !! with it along the normal. vel is the node velocity after the update; on return it is the
  !! constrained velocity, and dp the momentum added to the node (mass * change). The other
  !! walls act at the material surface (mpm_surface_contact).
  pure subroutine wall_mirror_node(normal, vwall, xnode_dist, mass, vel, dp)
    real(wp), intent(in) :: normal(2)     !! unit normal into the material [-]
    real(wp), intent(in) :: vwall(2)      !! wall velocity over the step [m/s]
    real(wp), intent(in) :: xnode_dist    !! signed distance of the node from the plane, minus a
                                          !! round-off tolerance [m]
    real(wp), intent(in) :: mass          !! node mass [kg/m]
    real(wp), intent(inout) :: vel(2)     !! node velocity [m/s]
    real(wp), intent(out) :: dp(2)        !! momentum added to the node [kg m/s per m]
    real(wp) :: vrel(2)
    dp = 0.0_wp
    if (xnode_dist > 0.0_wp) return
    vrel = vel - vwall
    vrel = vrel - dot_product(vrel, normal)*normal
    dp = mass*(vrel + vwall - vel)
    vel = vrel + vwall
  end subroutine wall_mirror_node

  !> Write the evolving part of each wall (point, impulse, force, work, impulse sum) to the
  !! open unformatted stream unit u (a checkpoint record); the prescribed motion comes from
  !! the input.
  subroutine walls_write_state(walls, u, stat, errmsg)
    type(wall_t), intent(in) :: walls(:)      !! the walls
    integer, intent(in) :: u                  !! unit, open for unformatted stream output
    integer, intent(out) :: stat              !! 0 or the iostat of the failed write
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    integer :: k
    write(u, iostat=stat, iomsg=errmsg) size(walls)
    do k = 1, size(walls)
      if (stat == 0) write(u, iostat=stat, iomsg=errmsg) walls(k)%point, walls(k)%impulse, &
        walls(k)%force, walls(k)%work, walls(k)%impulse_acc
    end do
  end subroutine walls_write_state

  !> Read a record of walls_write_state into walls (stat = -1 when the wall count differs).
  subroutine walls_read_state(walls, u, stat, errmsg)
    type(wall_t), intent(inout) :: walls(:)   !! the walls, set up from the same input
    integer, intent(in) :: u                  !! unit, open for unformatted stream input
    integer, intent(out) :: stat              !! 0, -1 (another count) or the iostat
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    integer :: k, n
    read(u, iostat=stat, iomsg=errmsg) n
    if (stat /= 0) return
    if (n /= size(walls)) then
      stat = -1
      return
    end if
    do k = 1, n
      if (stat == 0) read(u, iostat=stat, iomsg=errmsg) walls(k)%point, walls(k)%impulse, &
        walls(k)%force, walls(k)%work, walls(k)%impulse_acc
    end do
  end subroutine walls_read_state
end module mpm_walls
