!> Wall-clock phase timers of the time step (for `make bench` and the run summary).
! SPDX-License-Identifier: MIT
!
! The solver adds the wall time of each phase of a step to sim_t%phase_time(PHASE_*); reading
! the clock costs about 25 ns, a dozen times per step, so the timers are always on.
module mpm_timers
  use mpm_kinds, only: wp, i8
  implicit none
  private
  public :: clock_seconds, n_phases, phase_names
  public :: PHASE_BASIS, PHASE_P2G, PHASE_GRID, PHASE_G2P, PHASE_REMAP, PHASE_STRESS, &
            PHASE_CORNERS, PHASE_OTHER

  integer, parameter :: PHASE_BASIS = 1    !! weights and gradients, particle binning
  integer, parameter :: PHASE_P2G = 2      !! grid reset, mass, momentum and force scatter
  integer, parameter :: PHASE_GRID = 3     !! grid update, damping, wall gaps and walls
  integer, parameter :: PHASE_G2P = 4      !! velocity and position update of the particles
  integer, parameter :: PHASE_REMAP = 5    !! MUSL momentum re-map, velocities, walls
  integer, parameter :: PHASE_STRESS = 6   !! velocity gradient, F, volume, stress, energy
  integer, parameter :: PHASE_CORNERS = 7  !! CPDI2 corners and centroids
  integer, parameter :: PHASE_OTHER = 8    !! time step, energy balance, the rest
  integer, parameter :: n_phases = 8       !! number of phases
  !> Short names of the phases (column headers of the benchmark table).
  character(len=8), parameter :: phase_names(n_phases) = [character(len=8) :: 'basis', &
    'p2g', 'grid', 'g2p', 'remap', 'stress', 'corners', 'other']

contains

  !> Monotonic wall clock [s] (system_clock with 64-bit counts: nanosecond resolution).
  function clock_seconds() result(t)
    real(wp) :: t
    integer(i8) :: count, rate
    call system_clock(count, rate)
    t = real(count, wp)/real(rate, wp)
  end function clock_seconds
end module mpm_timers
