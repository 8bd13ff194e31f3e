!> Test helpers that need the library: a case built in code, validated as an input file would
!! be (config_resolve) and set up (setup_sim), failing the program on the first error.
! SPDX-License-Identifier: MIT
module testing_sim
  use mpm_kinds, only: wp
  use testing, only: check
  use mpm_config, only: config_t, config_resolve
  use mpm_setup, only: setup_sim
  use mpm_solver, only: sim_t
  implicit none
  private
  public :: must_setup, inside_count

contains

  !> Validate the case (config_resolve), then set it up; stop at the first error.
  subroutine must_setup(cfg_in, s)
    type(config_t), intent(in) :: cfg_in   !! the case, as built
    type(sim_t), intent(out) :: s          !! the simulation set up from it
    type(config_t) :: cfg
    integer :: stat
    character(len=:), allocatable :: errmsg
    cfg = cfg_in
    call config_resolve(cfg, stat, errmsg)
    call check(stat == 0, 'config_resolve: '//errmsg)
    if (stat /= 0) error stop 1
    call setup_sim(cfg, s, stat, errmsg)
    call check(stat == 0, 'setup_sim: '//errmsg)
    if (stat /= 0) error stop 1
  end subroutine must_setup

  !> How many of the convex counter-clockwise quadrilaterals quad (corners xc) hold the point p
  !! (on an edge counts): the sampled no-gap, no-overlap check of a mesh.
  pure integer function inside_count(xc, quad, p) result(nin)
    real(wp), intent(in) :: xc(:,:)        !! corners [m]
    integer, intent(in) :: quad(:,:)       !! 4 corner ids per quadrilateral [-]
    real(wp), intent(in) :: p(2)           !! the point [m]
    integer :: k, j
    real(wp) :: pa(2), pb(2)
    logical :: inside
    nin = 0
    do k = 1, size(quad, 2)
      inside = .true.
      do j = 1, 4                          ! left of every edge
        pa = xc(:, quad(j, k))
        pb = xc(:, quad(1 + mod(j, 4), k))
        if ((pb(1) - pa(1))*(p(2) - pa(2)) - (pb(2) - pa(2))*(p(1) - pa(1)) < 0.0_wp) &
          inside = .false.
      end do
      if (inside) nin = nin + 1
    end do
  end function inside_count
end module testing_sim
