!> The input checks of a half or quarter model: what its mirror planes forbid.
! SPDX-License-Identifier: MIT
!
! A ring body with sector = 'half' is the part x >= cx of a ring symmetric about the plane
! x = cx; 'quarter' is also symmetric about y = cy (mpm_particles; (cx, cy) is the centre of
! the first sector body, mpm_setup adds the planes as 'slip' walls). What the model leaves out
! is the mirror image of what it holds, so everything must be symmetric: a velocity component
! normal to a mirror plane is mirrored into the opposite one, which the full structure does not
! have, and the plane, which holds the material to it, hides the motion instead (a quarter
! ring given velocity (0, -5) never reaches the target; its kinetic energy falls from 10.6 to
! 3.2 J). Refused here with the group, the variable and what to change:
! - the velocity of every body and the gravity of &run: no component normal to a mirror plane;
! - a wall across a mirror plane (its normal perpendicular to the plane's): no velocity
!   component normal to the plane (its mirrored half would move the other way). A wall parallel
!   or oblique to a mirror plane stands for itself and its mirror image, a symmetric pair, and
!   may move in any direction (the crush's platen: its image is the other platen);
! - every sector ring centred on the mirror planes (the planes go through the first one's
!   centre);
! - every other body (a full ring, a rectangle) on the modelled side of the planes, within h/2:
!   one across a plane would overlap its own mirror image.
module mpm_symmetry
  use mpm_kinds, only: wp
  use mpm_constants, only: SHAPE_RING, SECTOR_FULL, SECTOR_HALF, SECTOR_QUARTER
  use mpm_config_types, only: config_t
  use mpm_config_text, only: itoa, fmt_short, fmt_list
  use mpm_config_scan, only: reader_t, occurrence, err_var
  use mpm_bodies, only: body_low, has_sector
  implicit none
  private
  public :: symmetry_checks

contains

  !> The checks of a half or quarter model (nothing to do for full models).
  subroutine symmetry_checks(rd, cfg)
    type(reader_t), intent(inout) :: rd    !! the input's occurrences and messages
    type(config_t), intent(in) :: cfg      !! the case, group checks done
    integer :: k, m, nm, first, io
    real(wp) :: normals(2, 2), center(2), reach
    character(len=40) :: plane(2)
    character(len=:), allocatable :: model, why
    first = 0
    why = ''
    do k = 1, size(cfg%bodies)
      io = occurrence(rd, 'body', k)
      if (io == 0) cycle
      if (.not. rd%occ(io)%ok) cycle
      if (has_sector(cfg%bodies(k)%shape_id) .and. cfg%bodies(k)%sector_id /= SECTOR_FULL) then
        first = k
        exit
      end if
    end do
    if (first == 0) return
    center = cfg%bodies(first)%center
    normals(:, 1) = [1.0_wp, 0.0_wp]
    normals(:, 2) = [0.0_wp, 1.0_wp]
    nm = 1
    model = 'half'
    if (cfg%bodies(first)%sector_id == SECTOR_QUARTER) then
      nm = 2
      model = 'quarter'
    end if
    plane = [character(len=40) :: 'x = '//fmt_short(center(1)), 'y = '//fmt_short(center(2))]
    model = 'the '//model//' model of &body #'//itoa(first)//' (mirror '// &
            trim(merge('planes', 'plane ', nm == 2))//' '//trim(plane(1))
    if (nm == 2) model = model//' and '//trim(plane(2))
    model = model//')'

    do k = 1, size(cfg%bodies)             ! bodies: velocity, centre of the other sectors
      io = occurrence(rd, 'body', k)
      if (io == 0) cycle
      if (.not. rd%occ(io)%ok) cycle
      associate (b => cfg%bodies(k))
        do m = 1, nm
          if (normal_part(b%velocity, normals(:, m))) call err_var(rd, io, 'velocity', &
            fmt_list(b%velocity), 'moves across the mirror plane '//trim(plane(m))//' of '// &
            model//': the mirror holds the body there, and its mirror image would move the '// &
            'other way', 'velocity('//itoa(m)//') = 0 (motion along the mirror '// &
            trim(merge('planes', 'plane ', nm == 2))//'), or sector = ''full'' for the '// &
            'whole structure')
        end do
        if (k /= first .and. has_sector(b%shape_id) .and. b%sector_id /= SECTOR_FULL) then
          if (b%center(1) /= center(1) .or. (nm == 2 .and. b%center(2) /= center(2))) &
            call err_var(rd, io, 'center', fmt_list(b%center), 'not on the mirror '// &
              trim(merge('planes', 'plane ', nm == 2))//' of '//model, &
              'the centre of &body #'//itoa(first)// &
              ' ('//fmt_list(center)//'), or sector = ''full''')
        end if
        if (.not. has_sector(b%shape_id) .or. b%sector_id == SECTOR_FULL) then
          do m = 1, nm                     ! a whole body: on the modelled side
            reach = center(m) - body_low(b, normals(:, m))
            if (reach > 0.5_wp*cfg%grid%h) then
              why = 'reaches '//fmt_short(reach)//' m across the mirror plane '// &
                trim(plane(m))//' of '//model//' (more than h/2): its mirror image would '// &
                'overlap it'
              if (body_low(b, -normals(:, m)) >= -center(m) - 0.5_wp*cfg%grid%h) why = &
                'lies behind the mirror plane '//trim(plane(m))//' of '//model// &
                ', outside the part it computes'
              call err_var(rd, io, 'center', fmt_list(b%center), why, 'a centre with the '// &
                'whole body on the modelled side of the plane, or sector = ''full'' for '// &
                'every body (the whole structure)')
              exit
            end if
          end do
        end if
      end associate
    end do

    io = occurrence(rd, 'run', 1)          ! gravity
    if (io > 0) then
      if (rd%occ(io)%ok) then
        do m = 1, nm
          if (normal_part(cfg%run%gravity, normals(:, m))) call err_var(rd, io, 'gravity', &
            fmt_list(cfg%run%gravity), 'pulls across the mirror plane '//trim(plane(m))// &
            ' of '//model//': the mirror image would be pulled the other way', &
            'gravity('//itoa(m)//') = 0, or sector = ''full'' for the whole structure')
        end do
      end if
    end if

    do k = 1, size(cfg%walls)              ! walls across a mirror plane
      if (cfg%walls(k)%mirror) cycle
      io = occurrence(rd, 'wall', k)
      if (io == 0) cycle
      if (.not. rd%occ(io)%ok) cycle
      associate (w => cfg%walls(k))
        do m = 1, nm
          if (abs(dot_product(w%normal, normals(:, m))) > 1.0e-9_wp*norm2(w%normal)) cycle
          if (normal_part(w%velocity, normals(:, m))) call err_var(rd, io, 'velocity', &
            fmt_list(w%velocity), 'the wall crosses the mirror plane '//trim(plane(m))// &
            ' of '//model//' and moves across it: its mirrored half would move the other '// &
            'way', 'velocity('//itoa(m)//') = 0 for a wall across the mirror plane, or '// &
            'sector = ''full'' for the whole structure')
        end do
      end associate
    end do
  end subroutine symmetry_checks

  !> v has a component along the unit vector n.
  pure logical function normal_part(v, n)
    real(wp), intent(in) :: v(2)           !! vector
    real(wp), intent(in) :: n(2)           !! unit normal of a mirror plane
    normal_part = dot_product(v, n) /= 0.0_wp
  end function normal_part
end module mpm_symmetry
