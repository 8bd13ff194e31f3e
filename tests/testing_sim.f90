!> Test helpers that need the library: a case built in code, validated as an input file would
!! be (config_resolve) and set up (setup_sim), failing the program on the first error.
! SPDX-License-Identifier: MIT
module testing_sim
  use testing, only: check
  use mpm_config, only: config_t, config_resolve
  use mpm_setup, only: setup_sim
  use mpm_solver, only: sim_t
  implicit none
  private
  public :: must_setup

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
end module testing_sim
