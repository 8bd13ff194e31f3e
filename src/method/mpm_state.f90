!> The simulation's data, split by lifetime: parameters (set once, never changed by a step),
!! the state (what a checkpoint holds), the work arrays of a step, and diagnostics.
! SPDX-License-Identifier: MIT
!
! sim_t extends state_t: s%p, s%walls, s%t, s%e_kin ... are the state, and s%state_t is all of
! it at once (what mpm_restart writes). The rest of sim_t is rebuilt or refilled by every step:
!   s%prm    params_t   copied from the input by mpm_setup, read-only in the step
!   s%g      grid_t     node fields (mpm_grid); its placement is also written to checkpoints
!   s%tiles  tiles_t    tiles, live spans and colour groups of the particles (mpm_tiles)
!   s%bufs   buffers_t  per-thread scatter buffers (mpm_grid)
!   s%wk     work_t     basis cache and per-particle work arrays of the step
!   s%diag   diag_t     what is measured about the run but never feeds back into it
! Each step phase takes the parts it reads and writes (mpm_weights, mpm_tiles, mpm_transfer,
! mpm_contact, mpm_deformation), never the whole sim_t.
module mpm_state
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: BASIS_CPDI2, SCHEME_MUSL, VOLUMETRIC_STANDARD
  use mpm_particles, only: particles_t, particles_write, particles_read
  use mpm_grid, only: grid_t, buffers_t
  use mpm_tiles, only: tiles_t
  use mpm_walls, only: wall_t, walls_write_state, walls_read_state
  use mpm_surface_contact, only: surface_work_t
  use mpm_contact_law, only: field_contact_t
  use mpm_self_contact, only: self_weld_t
  use mpm_body_tie, only: body_tie_t
  use mpm_material, only: material_t
  use mpm_timers, only: n_phases
  use mpm_strings, only: itoa, rtoa
  implicit none
  private
  public :: params_t, state_t, work_t, diag_t, sim_t, chunk, state_context
  public :: state_write, state_read, diag_write, diag_read

  integer, parameter :: chunk = 1024       !! particles per partial sum and per parallel chunk [-]

  !> Parameters of the step: copied from the input at set-up, never changed by a step.
  type :: params_t
    type(material_t), allocatable :: mats(:)  !! materials
    integer :: basis = BASIS_CPDI2         !! BASIS_* code
    integer :: scheme = SCHEME_MUSL        !! SCHEME_* code
    integer :: plane = 1                   !! PLANE_* code
    integer :: volumetric = VOLUMETRIC_STANDARD  !! VOLUMETRIC_* code: 'fbar' averages the
                                           !! volume change over each node's particles
    real(wp) :: flip = 1.0_wp              !! FLIP fraction [-]
    real(wp) :: damping = 0.0_wp           !! mass-proportional damping [1/s]
    real(wp) :: cfl = 0.0_wp               !! Courant number, given or automatic [-]
    real(wp) :: dt_fixed = 0.0_wp          !! fixed time step if > 0 [s]
    real(wp) :: t_end = 0.0_wp             !! end time [s]
    real(wp) :: gravity(2) = 0.0_wp        !! body acceleration [m/s^2]
    real(wp), allocatable :: bacc(:,:)     !! optional per-particle body acceleration (2, np)
                                           !! [m/s^2] (tests with manufactured solutions)
    real(wp) :: c_max = 0.0_wp             !! largest dilatational wave speed [m/s]
    real(wp) :: energy_tol = 0.2_wp        !! energy growth that counts as blow-up [-]
    real(wp) :: growth_tol = 0.05_wp       !! energy growth, relative to max(E0, external
                                           !! work, e_floor), that counts as unstable [-]:
                                           !! runs well below the stable time step lose
                                           !! energy; near it they gain up to 4.7 %
                                           !! (docs/stability.md)
    real(wp) :: e_floor = 0.0_wp           !! kinetic energy of the bodies at the largest wall
                                           !! speed: the energy scale of the start of a
                                           !! crush, when the work done is still tiny [J/m]
    logical :: deterministic = .false.     !! results independent of the thread count
    logical :: surface_curve = .true.      !! CPDI2 wall contact on the surface curve
                                           !! (mpm_surface_curve), else on the corners
    real(wp) :: max_nodes = 2147483647.0_wp  !! most grid nodes a fitted grid may grow to:
                                           !! what the memory available holds (mpm_budget) [-]
    integer :: parallel_min = 4096         !! particles from which loops run in parallel: below,
                                           !! OpenMP start-up and barriers cost more than they save
    integer :: colour_band = 32768         !! particles per band of the deterministic sweep
    ! contact between bodies (mpm_body_contact): one velocity field per body where there are
    ! several (nf = 1: one field for all, the arrays below not allocated)
    integer :: nf = 1                      !! velocity fields per node
    integer :: nbody = 1                   !! bodies
    integer :: npair = 0                   !! pairs of bodies i < j (nbody (nbody - 1) / 2)
    integer, allocatable :: field(:)       !! field of each particle (np)
    integer, allocatable :: corner_field(:)  !! field of each CPDI2 corner (nc)
    integer, allocatable :: field_body(:)  !! body of each field (nf)
    integer, allocatable :: pair_law(:,:)  !! CONTACT_* law between bodies i and j (nbody,
                                           !! nbody)
    real(wp), allocatable :: pair_mu(:,:)  !! their Coulomb coefficient (nbody, nbody) [-]
    integer, allocatable :: self_bond(:)   !! a ring with self-contact (mpm_self_contact): the
                                           !! field each particle is welded to at the seams, or
                                           !! 0 (np; allocated only with self-contact)
    type(body_tie_t) :: ties               !! 'bonded' pairs of bodies: their ties (mpm_body_tie)
  end type params_t

  !> The state: everything a checkpoint holds (with the grid placement and diag_t's extremes).
  type :: state_t
    type(particles_t) :: p                 !! particles
    type(wall_t), allocatable :: walls(:)  !! rigid walls (prescribed motion and reactions)
    integer :: nwall = 0                   !! number of walls
    real(wp) :: t = 0.0_wp                 !! time [s]
    real(wp) :: dt = 0.0_wp                !! last time step [s]
    integer(i8) :: step = 0_i8             !! steps done
    real(wp) :: vmax = 0.0_wp              !! largest particle speed [m/s]
    ! energies per unit depth of the modelled part [J/m]
    real(wp) :: e_kin = 0.0_wp, e_strain = 0.0_wp, e_plastic = 0.0_wp
    real(wp) :: e_external = 0.0_wp, e_damped = 0.0_wp, e0 = 0.0_wp
    real(wp) :: w_gravity = 0.0_wp         !! work of gravity and body forces [J/m]
    real(wp) :: e_contact = 0.0_wp         !! energy stored in the walls' contact, as the last
                                           !! step conserves it (mpm_contact) [J/m]
                                           !! (recomputed from the positions: not written)
    real(wp) :: e_contact_loss = 0.0_wp    !! energy lost to the walls' friction so far (not
                                           !! the contact between bodies') [J/m]
    real(wp) :: energy_error = 0.0_wp      !! largest |balance| / max(E0, largest |external|) [-]
    real(wp) :: bal_max = 0.0_wp           !! largest |kin + strain + plastic + damped + contact
                                           !! + contact_loss - ext - E0| [J/m]
    real(wp) :: ext_max = 0.0_wp           !! largest |external work| so far [J/m]
    real(wp), allocatable :: pair_acc(:,:) !! per pair of bodies i < j: normal impulse and the
                                           !! impulse on body i since the last history row
                                           !! (3, npair) [kg/s per m]
    real(wp), allocatable :: pair_force(:,:)  !! the same of the last step over dt (3, npair)
                                           !! [N/m]
  end type state_t

  !> Work arrays of a step: the basis cache and per-particle lists (no meaning between steps).
  type :: work_t
    integer :: nb = 0                      !! block width (nodes per direction)
    integer, allocatable :: blk(:,:)       !! lower-left node of each block (2, np)
    real(wp), allocatable :: w(:,:)        !! weights (nb*nb, np)
    real(wp), allocatable :: gw(:,:,:)     !! gradients (2, nb*nb, np) [1/m]
    logical :: par = .false.               !! loops run in parallel this step
    integer, allocatable :: tile(:)        !! grid tile of each particle's block (np)
    integer, allocatable :: perm(:)        !! particles sorted by tile (deterministic) (np)
    real(wp), allocatable :: chunk_sum(:,:) !! partial sums per chunk (3, nchunk)
    real(wp), allocatable :: vdamp(:,:)    !! damping's change of each node velocity in
                                           !! step 3 (2, nn*nf; damping > 0 only) [m/s]
    ! volumetric = 'fbar' only (mpm_fbar; allocated by the first step)
    real(wp), allocatable :: dj(:)         !! volume change over the step det(I + dt L) - 1 (np)
    real(wp), allocatable :: djbar(:)      !! its average over the neighbourhood (np) [-]
    real(wp), allocatable :: sforce(:,:)   !! stress of the internal forces (4, np) [Pa]
    real(wp), allocatable :: lgrad(:,:,:)  !! velocity gradient of the step (2, 2, np) [1/s]
    real(wp), allocatable :: node_sum(:,:) !! node sums of phi V q and phi V (2, nn)
    integer, allocatable :: column(:,:)    !! 'fbarwall': column through the wall and layer of
                                           !! each particle (2, np)
    real(wp), allocatable :: wall_work(:,:) !! per wall: velocity over the step, point, normal,
                                           !! velocity over the step before (8, nwall) [m/s, m, -]
    type(surface_work_t), allocatable :: surf(:)  !! per wall: surface points in contact
    type(field_contact_t) :: fc            !! contact between fields: nodes, pairs, gaps
    type(self_weld_t) :: sw                !! self-contact: the nodes where a ring's halves weld
    real(wp), allocatable :: tie_imp(:,:)  !! 'bonded' bodies: the ties' impulses of the step
    real(wp), allocatable :: tie_d(:,:)    !! 'bonded' bodies: each tie's stretch at the step's start [m]
                                           !! per pair (3, npair) [kg/s per m]
  end type work_t

  !> Diagnostics: measured, reported, never read back by the step. The extremes and the
  !! growth count go into checkpoints (mpm_restart), the phase times do not.
  type :: diag_t
    real(wp) :: phase_time(n_phases) = 0.0_wp  !! wall time spent per phase (mpm_timers) [s]
    real(wp) :: jmin_seen = 1.0_wp         !! smallest CPDI2 corner Jacobian ratio seen [-]
    real(wp) :: area_dev = 0.0_wp          !! largest |shoelace area / (J V0) - 1| seen [-]
    integer :: grown = 0                   !! times the grid was enlarged
  end type diag_t

  !> The whole simulation: the state, plus parameters, grid, work arrays and diagnostics.
  type, extends(state_t) :: sim_t
    type(params_t) :: prm                  !! parameters
    type(grid_t) :: g                      !! grid node fields
    type(tiles_t) :: tiles                 !! tiles, live spans, colour groups
    type(buffers_t) :: bufs                !! per-thread scatter buffers
    type(work_t) :: wk                     !! work arrays of the step
    type(diag_t) :: diag                   !! diagnostics
  end type sim_t

contains

  !> Where and when a step failed, for the messages: 'step N, t = T s, time step dt = X s
  !! (cfl C)'.
  function state_context(st, prm, h) result(text)
    type(state_t), intent(in) :: st        !! state (st%dt is the step being taken)
    type(params_t), intent(in) :: prm      !! parameters
    real(wp), intent(in) :: h              !! cell size [m]
    character(len=:), allocatable :: text
    text = 'step '//itoa(st%step + 1_i8)//', t = '//rtoa(st%t)//' s, time step dt = '// &
           rtoa(st%dt)//' s (cfl '//rtoa(st%dt*(prm%c_max + st%vmax)/h)//')'
  end function state_context

  !> Write the state to the open unformatted stream unit u (a checkpoint record): time and
  !! energies, then the walls and the particles, each written by its own module.
  subroutine state_write(st, u, stat, errmsg)
    type(state_t), intent(in) :: st           !! state
    integer, intent(in) :: u                  !! unit, open for unformatted stream output
    integer, intent(out) :: stat              !! 0 or the iostat of the failed write
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    write(u, iostat=stat, iomsg=errmsg) st%t, st%step, st%dt, st%vmax, st%e_kin, st%e_strain, &
      st%e_plastic, st%e_external, st%e_damped, st%e0, st%w_gravity, st%energy_error, &
      st%bal_max, st%ext_max, st%e_contact_loss
    if (stat == 0) call walls_write_state(st%walls, u, stat, errmsg)
    if (stat == 0) call particles_write(st%p, u, stat, errmsg)
    if (stat == 0 .and. allocated(st%pair_acc)) write(u, iostat=stat, iomsg=errmsg) &
      st%pair_acc, st%pair_force
  end subroutine state_write

  !> Read a record of state_write into st, which mpm_setup has built from the same input
  !! (stat = -1 when the wall, particle or corner counts differ).
  subroutine state_read(st, u, stat, errmsg)
    type(state_t), intent(inout) :: st        !! state, set up from the input
    integer, intent(in) :: u                  !! unit, open for unformatted stream input
    integer, intent(out) :: stat              !! 0, -1 (other counts) or the iostat
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    read(u, iostat=stat, iomsg=errmsg) st%t, st%step, st%dt, st%vmax, st%e_kin, st%e_strain, &
      st%e_plastic, st%e_external, st%e_damped, st%e0, st%w_gravity, st%energy_error, &
      st%bal_max, st%ext_max, st%e_contact_loss
    if (stat == 0) call walls_read_state(st%walls, u, stat, errmsg)
    if (stat == 0) call particles_read(st%p, u, stat, errmsg)
    if (stat == 0 .and. allocated(st%pair_acc)) read(u, iostat=stat, iomsg=errmsg) &
      st%pair_acc, st%pair_force
  end subroutine state_read

  !> Write the diagnostics that span the run (extremes, growth count; not the phase times).
  subroutine diag_write(diag, u, stat, errmsg)
    type(diag_t), intent(in) :: diag          !! diagnostics
    integer, intent(in) :: u                  !! unit, open for unformatted stream output
    integer, intent(out) :: stat              !! 0 or the iostat of the failed write
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    write(u, iostat=stat, iomsg=errmsg) diag%grown, diag%jmin_seen, diag%area_dev
  end subroutine diag_write

  !> Read a record of diag_write.
  subroutine diag_read(diag, u, stat, errmsg)
    type(diag_t), intent(inout) :: diag       !! diagnostics
    integer, intent(in) :: u                  !! unit, open for unformatted stream input
    integer, intent(out) :: stat              !! 0 or the iostat of the failed read
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    read(u, iostat=stat, iomsg=errmsg) diag%grown, diag%jmin_seen, diag%area_dev
  end subroutine diag_read
end module mpm_state
