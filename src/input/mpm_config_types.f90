!> The case description as read from a namelist file: one derived type per namelist group.
! SPDX-License-Identifier: MIT
!
! Each input variable is declared once: as a component of its group's type, with its default.
! The reader reads a group's text into a record of this type with the compiler's namelist
! read (mpm_config_record); the table of input variables (mpm_config_table) says what each
! one accepts and means. Components that are not input variables (the codes *_id, counts,
! flags) are set by the checks. A scene builder sets the components in code.
module mpm_config_types
  use mpm_kinds, only: wp
  use mpm_constants, only: name_len, path_len, max_table, SHAPE_RING
  use mpm_material, only: material_cfg_t   ! &material: the model owns its parameters
  use mpm_bodies, only: body_cfg_t, body_in_t  ! &body: the shapes own theirs
  implicit none
  private
  public :: config_t, run_cfg_t, solver_cfg_t, grid_cfg_t, material_cfg_t, body_cfg_t, &
            body_in_t, wall_cfg_t, probe_cfg_t, contact_cfg_t
  public :: unset_real, scene_of, stiffest_penalty

  type :: run_cfg_t
    character(len=name_len) :: title = ''          !! label of the case
    character(len=path_len) :: output_dir = ''     !! folder for all outputs
    real(wp) :: t_end = -1.0_wp                    !! simulated time [s]
    real(wp) :: cfl = 0.0_wp                       !! Courant number (0 = automatic) [-]
    real(wp) :: dt = 0.0_wp                        !! fixed time step if > 0 [s]
    real(wp) :: history_every = 0.0_wp             !! history interval [s]
    real(wp) :: snapshot_every = 0.0_wp            !! snapshot interval [s]
    real(wp) :: checkpoint_every = 0.0_wp          !! wall-clock checkpoint interval [s]
    real(wp) :: depth = 1.0_wp                     !! out-of-plane length [m]
    real(wp) :: gravity(2) = 0.0_wp                !! body acceleration [m/s^2]
    integer :: threads = 0                         !! OpenMP threads (0 = runtime default)
    logical :: mirror_images = .true.              !! snapshots of a sector show the whole tube
    logical :: end_at_release = .false.            !! end the run when its contact is over
    logical :: check_units = .true.                !! refuse values in a likely wrong unit
  end type run_cfg_t

  !> &solver
  type :: solver_cfg_t
    character(len=name_len) :: basis = 'cpdi2'     !! linear | ugimp | cpdi1 | cpdi2
    character(len=name_len) :: scheme = 'musl'     !! usl | usf | musl
    character(len=name_len) :: plane = 'strain'    !! strain | stress
    character(len=name_len) :: volumetric = 'standard'  !! standard | fbar
    integer :: basis_id = 0, scheme_id = 0, plane_id = 0, volumetric_id = 0  !! mpm_constants codes
    real(wp) :: flip = 1.0_wp                      !! FLIP fraction [-]
    real(wp) :: mass_scale = 1.0_wp                !! density multiplier [-]
    real(wp) :: damping = 0.0_wp                   !! mass-proportional damping [1/s]
    logical :: deterministic = .false.             !! thread-count independent results
  end type solver_cfg_t

  !> &grid
  type :: grid_cfg_t
    real(wp) :: h = -1.0_wp                        !! cell size [m]
    real(wp) :: lower(2) = 0.0_wp                  !! lower domain corner [m]
    real(wp) :: upper(2) = 0.0_wp                  !! upper domain corner [m]
    logical :: fitted = .true.                     !! lower/upper not given: fit to the scene
  end type grid_cfg_t

  !> &wall (repeatable)
  type :: wall_cfg_t
    real(wp) :: point(2) = 0.0_wp                  !! point on the plane at t = 0 [m]
    real(wp) :: normal(2) = 0.0_wp                 !! unit normal into the material side [-]
    character(len=name_len) :: contact = 'frictionless'  !! frictionless|coulomb|stick|slip
    integer :: contact_id = 0                      !! code of mpm_constants
    real(wp) :: friction = 0.0_wp                  !! Coulomb coefficient [-]
    real(wp) :: velocity(2) = 0.0_wp               !! prescribed velocity [m/s]
    real(wp) :: ramp = 0.0_wp                      !! smooth rise time of the velocity [s]
    integer :: n_motion = 0                        !! points in the motion table
    real(wp) :: motion_t(max_table) = 0.0_wp       !! table times [s]
    real(wp) :: motion_f(max_table) = 0.0_wp       !! table factors on velocity [-]
    real(wp) :: mass = 0.0_wp                      !! > 0: a free rigid body of this mass [kg]
    real(wp) :: stroke = 0.0_wp                    !! > 0: eases to rest at this travel [m]
    real(wp) :: penalty = 1.0_wp                   !! penalty stiffness over the default [-]
    logical :: mirror = .false.                    !! added by a body sector (not in the input)
  end type wall_cfg_t

  !> &probe (repeatable)
  type :: probe_cfg_t
    real(wp) :: point(2) = 0.0_wp                  !! the particle nearest at t = 0 is recorded [m]
  end type probe_cfg_t

  !> &contact (repeatable): how two bodies meet
  type :: contact_cfg_t
    integer :: bodies(2) = 0                       !! the two bodies (0, 0: every other pair)
    character(len=name_len) :: law = 'frictionless'  !! frictionless | coulomb | stick | bonded
    integer :: law_id = 0                          !! code of mpm_constants (CONTACT_*)
    real(wp) :: friction = 0.0_wp                  !! Coulomb coefficient [-]
  end type contact_cfg_t

  !> The whole case.
  type :: config_t
    character(len=path_len) :: file = ''           !! the namelist file read
    type(run_cfg_t) :: run
    type(solver_cfg_t) :: solver
    type(grid_cfg_t) :: grid
    type(material_cfg_t), allocatable :: materials(:)
    type(body_cfg_t), allocatable :: bodies(:)
    type(wall_cfg_t), allocatable :: walls(:)
    type(probe_cfg_t), allocatable :: probes(:)
    type(contact_cfg_t), allocatable :: contacts(:)
  end type config_t

  !> Marks a number that was not given: the points and normals of default_config, and the
  !! entries of a table (a tube's vertices; the reader starts a wall's motion table and a
  !! foam's curve from it) beyond the last one given.
  real(wp), parameter :: unset_real = huge(1.0_wp)

contains

  !> Which study scene the case resembles: 'impact' (a wall with mass: a drop weight), 'wave'
  !! (a wall gives a blow: a motion table that ends at rest), 'crush' (a platen keeps moving),
  !! 'impact' (a ring body moves at t = 0), or
  !! '' (generic). The only classifier: summary.nml's scene and `tubempm --scene` print it, and
  !! the plots read those.
  pure function scene_of(cfg) result(scene)
    type(config_t), intent(in) :: cfg     !! the case
    character(len=6) :: scene
    integer :: k
    scene = ''
    if (.not. any(cfg%bodies%shape_id == SHAPE_RING)) return
    if (any(cfg%walls%mass > 0.0_wp)) then  ! a drop weight
      scene = 'impact'
      return
    end if
    do k = 1, size(cfg%walls)
      if (cfg%walls(k)%n_motion < 1) cycle
      if (any(cfg%walls(k)%velocity /= 0.0_wp) .and. &
          cfg%walls(k)%motion_f(cfg%walls(k)%n_motion) == 0.0_wp) then
        scene = 'wave'
        return
      end if
    end do
    do k = 1, size(cfg%walls)
      if (any(cfg%walls(k)%velocity /= 0.0_wp)) then
        scene = 'crush'
        return
      end if
    end do
    do k = 1, size(cfg%bodies)
      if (cfg%bodies(k)%shape_id == SHAPE_RING .and. any(cfg%bodies(k)%velocity /= 0.0_wp)) then
        scene = 'impact'
        return
      end if
    end do
  end function scene_of

  !> The largest &wall penalty of the case, at least 1 (the automatic cfl is divided by it).
  pure real(wp) function stiffest_penalty(cfg) result(p)
    type(config_t), intent(in) :: cfg     !! the case
    p = maxval([1.0_wp, cfg%walls%penalty])
  end function stiffest_penalty
end module mpm_config_types
