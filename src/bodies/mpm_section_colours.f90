!> The colours of a section's walls for self-contact (mpm_self_contact): walls that can fold
!! onto each other must be in different velocity fields.
! SPDX-License-Identifier: MIT
!
! Two walls of one cell (an inner face of the wall graph, traced counter-clockwise) that share
! no joint can meet when the cell collapses. section_colours colours the walls greedily, in
! wall order, so that no two such walls share a colour; walls that share a joint may share one
! (they are welded there anyway). The joints where walls of two colours meet are the seams,
! welded as a ring's are (docs/method.md, "Self-contact").
module mpm_section_colours
  use mpm_kinds, only: wp
  use mpm_sections, only: section_t, incident, max_deg
  implicit none
  private
  public :: section_colours

contains

  !> Colours of the logical walls (1, 2, ...): two walls on one cell (an inner face of the
  !! graph) that share no node get different colours (greedy, in wall order); ncol colours.
  pure subroutine section_colours(s, colour, ncol)
    type(section_t), intent(in) :: s
    integer, allocatable, intent(out) :: colour(:)   !! colour of each logical wall
    integer, intent(out) :: ncol
    type :: list_t
      integer, allocatable :: v(:)
    end type list_t
    type(list_t), allocatable :: face(:), wface(:), wnode(:)
    integer :: nw, k, f, i, j, jj, a, b, he, h0, deg, inc(max_deg), ends(max_deg), pos, nf
    real(wp) :: ang(max_deg), area
    logical, allocatable :: seen(:,:), used(:)
    integer, allocatable :: facew(:)
    nw = maxval(s%ew)
    allocate(wnode(nw), wface(nw), seen(2, s%ne), face(0))
    do i = 1, nw
      allocate(wnode(i)%v(0), wface(i)%v(0))
    end do
    do k = 1, s%ne                          ! the nodes of each logical wall
      wnode(s%ew(k))%v = [wnode(s%ew(k))%v, s%en(:, k)]
    end do
    seen = .false.
    nf = 0
    do f = 1, s%ne                          ! trace the faces: half-edge (wall, direction)
      do k = 1, 2
        if (seen(k, f)) cycle
        allocate(facew(0))
        area = 0.0_wp
        he = f
        h0 = k
        do
          seen(h0, he) = .true.
          facew = [facew, s%ew(he)]
          a = s%en(h0, he)                  ! the half-edge goes from a to b
          b = s%en(3 - h0, he)
          area = area + s%xn(1, a)*s%xn(2, b) - s%xn(1, b)*s%xn(2, a)
          call incident(s, b, deg, inc, ends, ang)
          pos = 0
          do i = 1, deg
            if (inc(i) == he .and. ends(i) == 3 - h0) pos = i
          end do
          pos = 1 + modulo(pos - 2, deg)    ! the next wall clockwise at b
          he = inc(pos)
          h0 = ends(pos)
          if (seen(h0, he)) exit
        end do
        if (area > 0.0_wp) then             ! an inner face (counter-clockwise): a cell
          nf = nf + 1
          face = [face, list_t(facew)]
          do i = 1, size(facew)
            if (.not. any(wface(facew(i))%v == nf)) wface(facew(i))%v = [wface(facew(i))%v, nf]
          end do
        end if
        deallocate(facew)
      end do
    end do
    allocate(colour(nw), used(nw + 1))
    colour = 0
    ncol = 1
    do i = 1, nw
      used = .false.
      do jj = 1, size(wface(i)%v)
        associate (fw => face(wface(i)%v(jj))%v)
          do k = 1, size(fw)
            j = fw(k)
            if (colour(j) == 0) cycle
            if (any_common(wnode(i)%v, wnode(j)%v)) cycle    ! adjacent: welded at the joint
            used(colour(j)) = .true.
          end do
        end associate
      end do
      colour(i) = findloc(used, .false., 1)
      ncol = max(ncol, colour(i))
    end do
  contains
    pure logical function any_common(x, y)
      integer, intent(in) :: x(:), y(:)
      integer :: m
      any_common = .false.
      do m = 1, size(x)
        if (any(y == x(m))) any_common = .true.
      end do
    end function any_common
  end subroutine section_colours

end module mpm_section_colours
