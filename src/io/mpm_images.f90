!> The mirror images of a half or quarter model, for output: the whole tube from its computed
!! sector (docs/output.md, "Mirror images").
! SPDX-License-Identifier: MIT
!
! A half model (the part x >= x_c) has one image, its reflection in the plane x = x_c; a quarter
! model (x >= x_c, y >= y_c) has three: in x = x_c, in y = y_c, and in both (the point
! reflection through the centre). A reflection in x = c maps x to 2c - x and, as a tensor
! transformation with R = diag(-1, 1): vx -> -vx, sxy -> -sxy, F12 -> -F12, F21 -> -F21; in
! y = c likewise with y, vy and the same shear terms. Scalars (mass, volume, eqps, body, sxx,
! syy, szz) are unchanged. A reflection reverses the turning sense of a quadrilateral, so the
! corner ids of an image in one plane are listed in reverse order to stay counter-clockwise
! (the image in both planes is a half turn: same order). The images are output only: the solver
! never sees them.
module mpm_images
  use mpm_kinds, only: wp
  use mpm_walls, only: wall_t
  implicit none
  private
  public :: images_t, images_of_walls, image_flips, mirror_arrays

  !> The mirror planes of a sector as output uses them.
  type :: images_t
    integer :: n = 1                       !! copies of the sector written: 1 (none), 2, 4
    logical :: across(2) = .false.         !! a mirror plane x = c(1), y = c(2)
    real(wp) :: c(2) = 0.0_wp              !! their positions [m]
  end type images_t

contains

  !> The images of a set-up: from its mirror planes (walls with `mirror`, normal (1, 0) or
  !! (0, 1)); none when `wanted` is false or there is no mirror plane.
  pure function images_of_walls(walls, wanted) result(im)
    type(wall_t), intent(in) :: walls(:)   !! the set-up's walls, mirror planes included
    logical, intent(in) :: wanted          !! &run mirror_images
    type(images_t) :: im
    integer :: k, d
    do k = 1, size(walls)
      if (.not. walls(k)%mirror) cycle
      d = maxloc(abs(walls(k)%normal), dim=1)   ! the axis the plane is normal to
      im%across(d) = .true.
      im%c(d) = walls(k)%point0(d)
    end do
    if (.not. wanted) im%across = .false.
    im%n = 2**count(im%across)
  end function images_of_walls

  !> Which axes copy k (0 = the computed sector, 1 .. n-1 the images) is reflected across:
  !! half: 1 = x; quarter: 1 = x, 2 = y, 3 = both.
  pure function image_flips(im, k) result(flip)
    type(images_t), intent(in) :: im       !! the images
    integer, intent(in) :: k               !! copy, 0 .. im%n - 1
    logical :: flip(2)
    flip = .false.
    if (k == 0) return
    if (im%across(1) .and. im%across(2)) then
      flip = [btest(k, 0), btest(k, 1)]
    else
      flip = im%across
    end if
  end function image_flips

  !> The whole-tube arrays: copy 0 (the sector as given) followed by its images, each of the
  !! size of the sector's arrays. Particles (2-D arrays by column): x (2, np), v (2, np), stress
  !! (4, np: xx, yy, xy, zz), F (4, np: F11, F21, F12, F22), scalars s (3, np: mass, volume,
  !! eqps), body (np); corners (2, nc) and quads (4, np: 0-based corner ids). image (n np) is
  !! the copy of each particle.
  pure subroutine mirror_arrays(im, x, v, stress, F, s, body, corners, quads, &
                                xw, vw, stressw, Fw, sw, bodyw, cornersw, quadsw, image)
    type(images_t), intent(in) :: im       !! the images
    real(wp), intent(in) :: x(:,:), v(:,:), stress(:,:), F(:,:), s(:,:)  !! the sector
    integer, intent(in) :: body(:), quads(:,:)  !! body ids, 0-based corner ids
    real(wp), intent(in) :: corners(:,:)   !! corner positions [m]
    real(wp), allocatable, intent(out) :: xw(:,:), vw(:,:), stressw(:,:), Fw(:,:), sw(:,:)
    integer, allocatable, intent(out) :: bodyw(:), quadsw(:,:), image(:)
    real(wp), allocatable, intent(out) :: cornersw(:,:)
    integer :: np, nc, k, d, a, b, ac, bc
    logical :: flip(2)
    np = size(x, 2)
    nc = size(corners, 2)
    allocate(xw(2, im%n*np), vw(2, im%n*np), stressw(4, im%n*np), Fw(4, im%n*np), &
             sw(size(s, 1), im%n*np), bodyw(im%n*np), quadsw(4, im%n*np), image(im%n*np), &
             cornersw(2, im%n*nc))
    do k = 0, im%n - 1
      a = k*np + 1
      b = (k + 1)*np
      ac = k*nc + 1
      bc = (k + 1)*nc
      flip = image_flips(im, k)
      xw(:, a:b) = x
      vw(:, a:b) = v
      stressw(:, a:b) = stress
      Fw(:, a:b) = F
      sw(:, a:b) = s
      bodyw(a:b) = body
      image(a:b) = k
      cornersw(:, ac:bc) = corners
      if (count(flip) == 1) then           ! reversed: counter-clockwise after one reflection
        quadsw(:, a:b) = quads([1, 4, 3, 2], :) + k*nc
      else                                 ! none, or two (a half turn keeps the sense)
        quadsw(:, a:b) = quads + k*nc
      end if
      do d = 1, 2
        if (.not. flip(d)) cycle
        xw(d, a:b) = 2.0_wp*im%c(d) - x(d, :)
        cornersw(d, ac:bc) = 2.0_wp*im%c(d) - corners(d, :)
        vw(d, a:b) = -v(d, :)
        stressw(3, a:b) = -stressw(3, a:b)  ! sxy changes sign once per reflection
        Fw(2:3, a:b) = -Fw(2:3, a:b)        ! F21 and F12 likewise
      end do
    end do
  end subroutine mirror_arrays
end module mpm_images
