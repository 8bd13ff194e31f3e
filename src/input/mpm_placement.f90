!> Where the bodies are at t = 0: apart from each other, and in front of every wall. Checked
!! after the lengths (a length in the wrong unit puts bodies behind walls and into each other).
! SPDX-License-Identifier: MIT
!
! Two bodies that overlap would occupy the same space: the contact between bodies acts only
! where their surfaces meet (mpm_body_contact), so it would not separate them, and with one
! velocity field they would move as one. A body behind a wall would be pushed through it at the
! first step. Both are refused, with a tolerance of half a cell (the particles' reach beyond
! the shape) and touching allowed.
module mpm_placement
  use mpm_kinds, only: wp
  use mpm_constants, only: CONTACT_SLIP
  use mpm_config_types, only: config_t
  use mpm_bodies, only: body_low, body_overlap, body_estimate
  use mpm_config_body, only: mesh_check_max
  use mpm_config_text, only: itoa, fmt_short, fmt_list
  use mpm_config_scan, only: reader_t, occurrence, err_var
  implicit none
  private
  public :: placement_checks

contains

  !> The bodies apart from each other and in front of every wall at t = 0.
  subroutine placement_checks(rd, cfg, occ_body)
    type(reader_t), intent(inout) :: rd    !! the input's occurrences and messages
    type(config_t), intent(in) :: cfg      !! the case, its lengths checked
    integer, intent(in) :: occ_body(:)     !! occurrence of each &body
    logical :: ok(size(occ_body))
    integer :: j
    real(wp) :: np, nc, ext
    do j = 1, size(occ_body)                 ! bodies meshed here: at most mesh_check_max
      ok(j) = rd%occ(occ_body(j))%ok       ! particles (the budget refuses larger ones)
      if (.not. ok(j)) cycle
      call body_estimate(cfg%bodies(j), np, nc, ext)
      ok(j) = np <= mesh_check_max
    end do
    call overlap_checks(rd, cfg, occ_body, ok)
    call wall_side_checks(rd, cfg, ok)
    call twin_walls(rd, cfg)
  end subroutine placement_checks

  !> A wall given twice (the same plane, normal and motion as an earlier one): a warning, as
  !! both act and share the contact force between them (each reports its share).
  subroutine twin_walls(rd, cfg)
    type(reader_t), intent(inout) :: rd    !! the input's occurrences and messages
    type(config_t), intent(in) :: cfg      !! the case
    integer :: j, k, io(size(cfg%walls))
    logical :: usable(size(cfg%walls))
    real(wp) :: n(2, size(cfg%walls))
    ! walls read without error and with a normal (one in error has been reported: no twin of
    ! it; a &wall without a normal divided by zero here before), with their unit normals
    do k = 1, size(cfg%walls)
      io(k) = occurrence(rd, 'wall', k)
      usable(k) = io(k) > 0
      if (usable(k)) usable(k) = rd%occ(io(k))%ok .and. norm2(cfg%walls(k)%normal) > 0.0_wp
      n(:, k) = 0.0_wp
      if (usable(k)) n(:, k) = cfg%walls(k)%normal/norm2(cfg%walls(k)%normal)
    end do
    do k = 2, size(cfg%walls)
      if (.not. usable(k)) cycle
      do j = 1, k - 1
        if (.not. usable(j)) cycle
        associate (a => cfg%walls(j), b => cfg%walls(k))
          if (any(abs(n(:, j) - n(:, k)) > 1.0e-12_wp) .or. &
              abs(dot_product(a%point - b%point, n(:, k))) > &
              1.0e-9_wp*cfg%grid%h .or. any(a%velocity /= b%velocity) .or. &
              a%ramp /= b%ramp .or. a%n_motion /= b%n_motion) cycle
          if (any(a%motion_t /= b%motion_t) .or. any(a%motion_f /= b%motion_f)) cycle
          call err_var(rd, io(k), 'point', '', 'the plane and motion of &wall #'//itoa(j)// &
            ': the two share the contact force. Delete one &wall', warn=.true.)
          exit
        end associate
      end do
    end do
  end subroutine twin_walls

  !> No two bodies overlapping by more than h/2 at t = 0; reported at the later body's centre.
  subroutine overlap_checks(rd, cfg, occ_body, ok)
    type(reader_t), intent(inout) :: rd    !! the input's occurrences and messages
    type(config_t), intent(in) :: cfg      !! the case
    integer, intent(in) :: occ_body(:)     !! occurrence of each &body
    logical, intent(in) :: ok(:)           !! each body read without error, and meshable
    integer :: i, j
    real(wp) :: depth
    do j = 2, size(cfg%bodies)
      if (.not. ok(j)) cycle
      do i = 1, j - 1
        if (.not. ok(i)) cycle
        depth = body_overlap(cfg%bodies(i), cfg%bodies(j))
        if (depth <= 0.5_wp*cfg%grid%h) cycle
        call err_var(rd, occ_body(j), 'center', fmt_list(cfg%bodies(j)%center), &
          'overlaps &body #'//itoa(i)//' by up to '//fmt_short(depth)//' m at t = 0 (more '// &
          'than h/2): the two would fill the same space, and contact acts only where '// &
          'surfaces meet', 'a centre (or size) that leaves the bodies apart or touching')
        exit
      end do
    end do
  end subroutine overlap_checks

  !> Every body in front of every wall at t = 0: a body more than half a cell behind a wall
  !! (its normal pointing away from the material, or its point inside the body) would be
  !! pushed through it at the first step; reported at the wall's normal, with the normal that
  !! would put the body in front. Mirror planes ('slip') hold material on both sides.
  subroutine wall_side_checks(rd, cfg, ok)
    type(reader_t), intent(inout) :: rd    !! the input's occurrences and messages
    type(config_t), intent(in) :: cfg      !! the case
    logical, intent(in) :: ok(:)           !! each body read without error, and meshable
    integer :: k, j, i, io
    real(wp) :: n(2), gap, flipped
    character(len=256) :: fix
    character(len=*), parameter :: any_fix = 'a unit normal pointing from the wall into the '// &
      'material, and a point with every body in front of it'
    do k = 1, size(cfg%walls)
      io = occurrence(rd, 'wall', k)
      if (io == 0) cycle
      if (.not. rd%occ(io)%ok .or. cfg%walls(k)%contact_id == CONTACT_SLIP) cycle
      n = cfg%walls(k)%normal
      do j = 1, size(cfg%bodies)
        if (.not. ok(j)) cycle
        gap = body_low(cfg%bodies(j), n) - dot_product(cfg%walls(k)%point, n)
        if (gap >= -0.5_wp*cfg%grid%h) cycle
        flipped = huge(1.0_wp)              ! the flip must put every body in front
        do i = 1, size(cfg%bodies)
          if (ok(i)) flipped = min(flipped, body_low(cfg%bodies(i), -n) + &
                                                    dot_product(cfg%walls(k)%point, n))
        end do
        fix = any_fix
        if (flipped >= -0.5_wp*cfg%grid%h) fix = 'normal = '//fmt_list(-n)//' (the material '// &
          'is on that side of the wall), or '//any_fix
        call err_var(rd, io, 'normal', fmt_list(n), '&body #'//itoa(j)//' lies up to '// &
          fmt_short(-gap)//' m behind the wall at t = 0 (more than h/2): its contact would '// &
          'push the material through the wall at the first step', trim(fix))
        exit
      end do
    end do
  end subroutine wall_side_checks
end module mpm_placement
