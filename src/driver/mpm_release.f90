!> `&run end_at_release`: end a run when its contact is over (a ring that has hit a target and
!! left it, two bodies that have collided and parted), so that an impact costs the steps of the
!! contact and not those of a t_end chosen before the contact time was known.
! SPDX-License-Identifier: MIT
!
! A step is "in contact" when a wall that is not a symmetry plane (a sector's mirror or a 'slip'
! wall: it carries the reaction of the missing half for the whole run) has a nonzero force or
! moves (a driven platen keeps the contact open: a crush never releases while the platen moves,
! though the struck wall may leave it for a while), or a pair of bodies has a positive normal
! force. The contact is over, and the run ends, at the first
! step after a contact that has been free of contact for the longer of
!   hold_fraction x (the time from the first to the last step in contact)  and  hold_steps steps;
! a contact that resumes within that time (chatter, a second bounce) continues the same
! contact. The two times are the driver's state and go into the checkpoint (mpm_restart).
module mpm_release
  use mpm_kinds, only: wp
  use mpm_constants, only: CONTACT_SLIP
  use mpm_walls, only: wall_t, wall_factor
  implicit none
  private
  public :: release_t, release_observe, release_due, in_contact

  real(wp), parameter :: hold_fraction = 0.1_wp  !! contact-free time / contact time [-]
  integer, parameter :: hold_steps = 50          !! contact-free steps at least [-]

  !> The contact seen so far.
  type :: release_t
    real(wp) :: t_first = -1.0_wp          !! time of the first step in contact (< 0: none) [s]
    real(wp) :: t_last = -1.0_wp           !! time of the last step in contact [s]
  end type release_t

contains

  !> Whether the step just taken had a contact force (walls other than symmetry planes, pairs
  !! of bodies) or a wall moving by its prescribed law.
  pure logical function in_contact(walls, pair_force, t) result(on)
    type(wall_t), intent(in) :: walls(:)   !! rigid walls, their force of the last step
    real(wp), intent(in) :: pair_force(:,:)  !! pairs' normal force and its components of the
                                             !! last step (3, npair) [N/m]
    real(wp), intent(in) :: t              !! time after the step [s]
    integer :: k
    on = .false.
    do k = 1, size(walls)
      if (walls(k)%mirror .or. walls(k)%contact == CONTACT_SLIP) cycle
      if (any(walls(k)%force /= 0.0_wp)) on = .true.
      if (walls(k)%mass > 0.0_wp) then       ! a drop weight: on while it moves into the
        if (walls(k)%vn > 0.0_wp) on = .true. ! material (it may lose touch for a moment)
        cycle
      end if
      if (any(wall_factor(walls(k), t)*walls(k)%velocity /= 0.0_wp)) on = .true.
    end do
    if (size(pair_force, 2) > 0) then
      if (any(pair_force(1, :) > 0.0_wp)) on = .true.
    end if
  end function in_contact

  !> Record the step just taken (time t after it; contact or not).
  pure subroutine release_observe(rel, t, on)
    type(release_t), intent(inout) :: rel  !! the contact seen so far
    real(wp), intent(in) :: t              !! time after the step [s]
    logical, intent(in) :: on              !! the step had a contact force
    if (.not. on) return
    if (rel%t_first < 0.0_wp) rel%t_first = t
    rel%t_last = t
  end subroutine release_observe

  !> Whether the contact is over at time t (the time step dt): a contact was seen and none
  !! for the hold time since.
  pure logical function release_due(rel, t, dt) result(due)
    type(release_t), intent(in) :: rel    !! the contact seen so far
    real(wp), intent(in) :: t              !! time now [s]
    real(wp), intent(in) :: dt             !! time step [s]
    due = .false.
    if (rel%t_first < 0.0_wp) return
    due = t - rel%t_last >= max(hold_fraction*(rel%t_last - rel%t_first), &
                                real(hold_steps, wp)*dt)*(1.0_wp - 1.0e-12_wp)
  end function release_due
end module mpm_release
