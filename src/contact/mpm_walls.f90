!> Rigid straight walls (platens, targets, mirror planes): the wall type, its prescribed motion
!! (with a stroke at which it eases to rest), the free motion of a wall with mass (a drop
!! weight), the mirror-plane rule on a node, and its checkpoint record (docs/method.md).
! SPDX-License-Identifier: MIT
!
! A 'slip' mirror plane acts on the grid nodes on or behind it (the grid has nodes on every
! mirror plane); the other walls act at the material surface (mpm_surface_contact, called from
! mpm_contact). The momentum a wall adds, divided by dt, is its force.
!
! A wall with mass moves along its normal under the reaction of the material and gravity,
! by the central difference of the particles (wall_free_step): its velocity over a step,
! v+ = v- + (g.n dt - I.n / M) with I the impulse it gave the material over the step, and its
! plane moves by v+ dt. Its work on the material is I.n (v- + v+)/2, so that its kinetic energy
! M v+^2 / 2 (that of the last step) falls by exactly that work less gravity's.
module mpm_walls
  use mpm_kinds, only: wp
  use mpm_constants, only: pi, max_table, CONTACT_FRICTIONLESS
  implicit none
  private
  public :: wall_t, wall_factor, wall_travel, wall_shift, wall_velocity, wall_mirror_node, &
            walls_write_state, walls_read_state, wall_free_step, wall_kinetic, &
            wall_stroke_setup, wall_stroke_travel, wall_end_time

  !> A rigid plane with prescribed motion, or free along its normal (mass > 0).
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
    real(wp) :: mass = 0.0_wp             !! > 0: free along the normal; the modelled part's
                                          !! mass per unit depth [kg/m]
    real(wp) :: stroke = 0.0_wp           !! > 0: the motion eases to rest at this travel [m]
    real(wp) :: penalty = 1.0_wp          !! penalty stiffness over the default alpha [-]
    real(wp) :: t_stroke = huge(1.0_wp)   !! time the easing starts [s] (wall_stroke_setup)
    real(wp) :: f_stroke = 0.0_wp         !! the velocity factor then [-]
    ! state, updated every step
    real(wp) :: point(2) = 0.0_wp         !! current point on the plane [m]
    real(wp) :: impulse(2) = 0.0_wp       !! impulse on the material this step [N s per depth]
    real(wp) :: force(2) = 0.0_wp         !! force of the material on the wall, last step [N/m]
    real(wp) :: impulse_acc(2) = 0.0_wp   !! impulse on the material since the last history row
    real(wp) :: work = 0.0_wp             !! work done on the material so far [J/m]
    real(wp) :: vn = 0.0_wp               !! mass > 0: velocity along the normal over the last
                                          !! step [m/s]
    real(wp) :: disp = 0.0_wp             !! mass > 0: travel along minus the normal [m]
    real(wp) :: w_gravity = 0.0_wp        !! mass > 0: gravity's work on the wall [J/m]
    real(wp) :: travel_max = 0.0_wp       !! mass > 0: its largest advance into the material [m]
  end type wall_t

contains

  !> Factor on the prescribed velocity at time t: smooth ramp (1 - cos)/2, or the table.
  pure function wall_factor(w, t) result(f)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: f
    if (t > w%t_stroke) then
      f = w%f_stroke*ease(w, t)
    else
      f = law_factor(w, t)
    end if
  end function wall_factor

  !> After the stroke time: the share of the velocity left, (1 + cos)/2 over ramp (0 without).
  pure function ease(w, t) result(e)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s], > t_stroke
    real(wp) :: e
    e = 0.0_wp
    if (w%ramp > 0.0_wp .and. t < w%t_stroke + w%ramp) &
      e = 0.5_wp*(1.0_wp + cos(pi*(t - w%t_stroke)/w%ramp))
  end function ease

  !> The factor of the ramp law or the table, without the stroke.
  pure function law_factor(w, t) result(f)
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
  end function law_factor

  !> Integral of the velocity factor from 0 to t [s] (exact for the ramp, the table and the
  !! stroke's easing).
  pure function factor_integral(w, t) result(s)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: s, tau
    if (t > w%t_stroke) then
      s = law_integral(w, w%t_stroke)
      if (w%ramp > 0.0_wp) then
        tau = min(t - w%t_stroke, w%ramp)/w%ramp
        s = s + w%f_stroke*0.5_wp*w%ramp*(tau + sin(pi*tau)/pi)
      end if
    else
      s = law_integral(w, t)
    end if
  end function factor_integral

  !> Integral of the law's factor (without the stroke) from 0 to t [s].
  pure function law_integral(w, t) result(s)
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
  end function law_integral

  !> The travel a stroke is measured in [m]: its normal part when the velocity has one (a
  !! platen's advance), else along the velocity (a platen that only shears).
  pure function wall_stroke_travel(w, t) result(d)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: d
    d = stroke_speed(w)*factor_integral(w, t)
  end function wall_stroke_travel

  !> The speed a stroke's travel grows with at factor 1 [m/s].
  pure function stroke_speed(w) result(v)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp) :: v
    v = abs(dot_product(w%velocity, w%normal))
    if (v <= 1.0e-12_wp*norm2(w%velocity)) v = norm2(w%velocity)
  end function stroke_speed

  !> The stroke's time: the first t at which the travel so far plus the travel of the easing,
  !! v f(t) ramp / 2, reaches the stroke (so that the wall comes to rest at it exactly), found
  !! by a scan and bisection of the law; ok = .false. when the law never travels that far (a
  !! table that comes to rest first). No stroke: t_stroke stays huge.
  pure subroutine wall_stroke_setup(w, ok)
    type(wall_t), intent(inout) :: w      !! the wall: t_stroke, f_stroke set
    logical, intent(out) :: ok            !! the stroke is reached
    real(wp) :: v, ta, tb, tm, tend, f_end
    integer :: k, n
    ok = .true.
    w%t_stroke = huge(1.0_wp)
    w%f_stroke = 0.0_wp
    if (.not. w%stroke > 0.0_wp) return
    v = stroke_speed(w)
    ok = .false.
    if (.not. v > 0.0_wp) return
    ! past the law's last change the factor is f_end: the stroke is reached within twice the
    ! time it takes at f_end, or never (f_end <= 0)
    tend = w%ramp
    if (w%n_motion > 0) tend = w%motion_t(w%n_motion)
    f_end = law_factor(w, tend + 1.0_wp)
    if (v*f_end > 0.0_wp) tend = tend + 2.0_wp*w%stroke/(v*f_end) + w%ramp
    n = 20000
    ta = 0.0_wp
    do k = 1, n
      tb = tend*real(k, wp)/real(n, wp)
      if (reach(tb) >= w%stroke) exit
      ta = tb
    end do
    if (reach(tb) < w%stroke) return
    do k = 1, 200
      tm = 0.5_wp*(ta + tb)
      if (tm <= ta .or. tm >= tb) exit
      if (reach(tm) >= w%stroke) then
        tb = tm
      else
        ta = tm
      end if
    end do
    w%t_stroke = tb
    w%f_stroke = law_factor(w, tb)
    ok = .true.
  contains
    pure real(wp) function reach(t)
      real(wp), intent(in) :: t
      reach = v*(law_integral(w, t) + 0.5_wp*w%ramp*law_factor(w, t))
    end function reach
  end subroutine wall_stroke_setup

  !> When the wall's motion is over: a stroke's end (t_stroke + ramp), huge without a stroke.
  pure function wall_end_time(w) result(t)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp) :: t
    t = huge(1.0_wp)
    if (w%t_stroke < huge(1.0_wp)) t = w%t_stroke + w%ramp
  end function wall_end_time

  !> A wall with mass after a step of length dt in which it gave the material the impulse
  !! w%impulse: its velocity over the step, its plane's travel, its work on the material and
  !! gravity's work on it (the central difference of the module's header).
  pure subroutine wall_free_step(w, gravity, dt)
    type(wall_t), intent(inout) :: w      !! the wall (mass > 0)
    real(wp), intent(in) :: gravity(2)    !! gravity [m/s^2]
    real(wp), intent(in) :: dt            !! the step [s]
    real(wp) :: vm, vp, gn
    vm = w%vn
    gn = dot_product(gravity, w%normal)
    vp = vm + gn*dt - dot_product(w%impulse, w%normal)/w%mass
    w%vn = vp
    w%disp = w%disp - dt*vp
    w%travel_max = max(w%travel_max, -w%disp)
    w%work = w%work + dot_product(w%impulse, w%normal)*0.5_wp*(vm + vp)
    w%w_gravity = w%w_gravity + w%mass*gn*dt*0.5_wp*(vm + vp)
  end subroutine wall_free_step

  !> Kinetic energy of a wall with mass, M v^2 / 2 with the velocity of the last step [J/m].
  pure function wall_kinetic(w) result(e)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp) :: e
    e = 0.5_wp*w%mass*w%vn**2
  end function wall_kinetic

  !> Prescribed wall velocity at time t [m/s]; a wall with mass: that of its last step.
  pure function wall_velocity(w, t) result(v)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: v(2)
    if (w%mass > 0.0_wp) then
      v = w%vn*w%normal
    else
      v = w%velocity*wall_factor(w, t)
    end if
  end function wall_velocity

  !> Point on the plane at time t [m] is point0 + velocity * integral of the factor; this
  !! returns the travel along minus the normal since t = 0 [m] and sets nothing. A wall with
  !! mass: its travel so far (t is not used).
  pure function wall_travel(w, t) result(d)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: d
    if (w%mass > 0.0_wp) then
      d = w%disp
    else
      d = -dot_product(w%velocity, w%normal)*factor_integral(w, t)
    end if
  end function wall_travel

  !> The wall's displacement since t = 0 [m]: its velocity times the integral of the factor
  !! (prescribed motion; a wall with mass moves along its normal only).
  pure function wall_shift(w, t) result(s)
    type(wall_t), intent(in) :: w         !! the wall
    real(wp), intent(in) :: t             !! time [s]
    real(wp) :: s(2)
    if (w%mass > 0.0_wp) then
      s = -w%disp*w%normal
    else
      s = w%velocity*factor_integral(w, t)
    end if
  end function wall_shift

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

  !> Write the evolving part of each wall (point, impulse, force, work, impulse sum; a free
  !! wall's velocity, travel and gravity work) to the
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
        walls(k)%force, walls(k)%work, walls(k)%impulse_acc, walls(k)%vn, walls(k)%disp, &
        walls(k)%w_gravity, walls(k)%travel_max
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
        walls(k)%force, walls(k)%work, walls(k)%impulse_acc, walls(k)%vn, walls(k)%disp, &
        walls(k)%w_gravity, walls(k)%travel_max
    end do
  end subroutine walls_read_state
end module mpm_walls
