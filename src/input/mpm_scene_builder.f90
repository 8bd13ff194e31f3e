!> Build a case in code (tests, the benchmark, tools): the groups of an input file as calls,
!! then config_resolve (mpm_config) validates and resolves it with the rules and messages of
!! the input file.
! SPDX-License-Identifier: MIT
!
!   cfg = scene_new('bar', t_end=1.0e-3_wp, h=1.0e-3_wp)
!   call scene_add_material(cfg, 'steel', MODEL_J2, E, nu, rho, sigma_y=310.0e6_wp)
!   call scene_add_ring(cfg, center, r_inner, r_outer, n_thick=8)
!   call scene_add_wall(cfg, point, normal, velocity=[0.0_wp, -5.0_wp])
!   call config_resolve(cfg, stat, errmsg)
!
! Everything not given keeps the default of the input file (docs/input.md).
module mpm_scene_builder
  use mpm_kinds, only: wp
  use mpm_constants, only: BASIS_CPDI2, SCHEME_MUSL, PLANE_STRAIN, RATE_NONE, SHAPE_RING, &
                           SHAPE_RECT, SECTOR_FULL, CONTACT_FRICTIONLESS
  use mpm_config_types, only: config_t, material_cfg_t, body_cfg_t, wall_cfg_t
  implicit none
  private
  public :: scene_new, scene_add_material, scene_add_ring, scene_add_rect, scene_add_wall

contains

  !> A case with &run, &solver and &grid (fitted) and no materials, bodies, walls or probes.
  function scene_new(title, t_end, h, basis, scheme, plane) result(cfg)
    character(len=*), intent(in) :: title          !! title, also the "file" of messages
    real(wp), intent(in) :: t_end                  !! simulated time [s]
    real(wp), intent(in) :: h                      !! cell size [m]
    integer, intent(in), optional :: basis, scheme, plane   !! BASIS_*, SCHEME_*, PLANE_*
    type(config_t) :: cfg
    cfg%file = title
    cfg%run%title = title
    cfg%run%t_end = t_end
    cfg%solver%basis_id = BASIS_CPDI2
    cfg%solver%scheme_id = SCHEME_MUSL
    cfg%solver%plane_id = PLANE_STRAIN
    if (present(basis)) cfg%solver%basis_id = basis
    if (present(scheme)) cfg%solver%scheme_id = scheme
    if (present(plane)) cfg%solver%plane_id = plane
    cfg%grid%h = h
    cfg%grid%fitted = .true.
    allocate(cfg%materials(0), cfg%bodies(0), cfg%walls(0), cfg%probes(0), cfg%contacts(0))
  end function scene_new

  !> Add a &material.
  subroutine scene_add_material(cfg, name, model, E, nu, rho, sigma_y, hardening, rate_law)
    type(config_t), intent(inout) :: cfg
    character(len=*), intent(in) :: name           !! label used by bodies
    integer, intent(in) :: model                   !! MODEL_* code
    real(wp), intent(in) :: E, nu, rho             !! [Pa], [-], [kg/m^3]
    real(wp), intent(in), optional :: sigma_y      !! initial yield stress [Pa]
    real(wp), intent(in), optional :: hardening    !! hardening modulus [Pa]
    integer, intent(in), optional :: rate_law      !! RATE_* code (default none)
    type(material_cfg_t) :: m
    m%name = name
    m%model_id = model
    m%rate_law_id = RATE_NONE
    if (present(rate_law)) m%rate_law_id = rate_law
    m%E = E
    m%nu = nu
    m%rho = rho
    if (present(sigma_y)) m%sigma_y = sigma_y
    if (present(hardening)) m%hardening = hardening
    cfg%materials = [cfg%materials, m]
  end subroutine scene_add_material

  !> Add a ring &body (made of the first material unless `material` names another).
  subroutine scene_add_ring(cfg, center, r_inner, r_outer, n_thick, velocity, sector, material)
    type(config_t), intent(inout) :: cfg
    real(wp), intent(in) :: center(2)              !! centre [m]
    real(wp), intent(in) :: r_inner, r_outer       !! radii [m]
    integer, intent(in) :: n_thick                 !! particles through the wall
    real(wp), intent(in), optional :: velocity(2)  !! initial velocity [m/s]
    integer, intent(in), optional :: sector        !! SECTOR_* code (default full)
    character(len=*), intent(in), optional :: material  !! a material name
    type(body_cfg_t) :: b
    b%shape_id = SHAPE_RING
    b%sector_id = SECTOR_FULL
    if (present(sector)) b%sector_id = sector
    b%center = center
    b%r_inner = r_inner
    b%r_outer = r_outer
    b%n_thick = n_thick
    b%n_circ = 0
    if (present(velocity)) b%velocity = velocity
    if (present(material)) b%material = material
    cfg%bodies = [cfg%bodies, b]
  end subroutine scene_add_ring

  !> Add a rectangular &body (made of the first material).
  subroutine scene_add_rect(cfg, center, size, n_x, n_y, velocity)
    type(config_t), intent(inout) :: cfg
    real(wp), intent(in) :: center(2), size(2)     !! centre, sides [m]
    integer, intent(in) :: n_x, n_y                !! particles along the sides
    real(wp), intent(in), optional :: velocity(2)  !! initial velocity [m/s]
    type(body_cfg_t) :: b
    b%shape_id = SHAPE_RECT
    b%sector_id = SECTOR_FULL
    b%center = center
    b%size = size
    b%n_x = n_x
    b%n_y = n_y
    if (present(velocity)) b%velocity = velocity
    cfg%bodies = [cfg%bodies, b]
  end subroutine scene_add_rect

  !> Add a frictionless &wall.
  subroutine scene_add_wall(cfg, point, normal, velocity)
    type(config_t), intent(inout) :: cfg
    real(wp), intent(in) :: point(2)               !! a point on the plane at t = 0 [m]
    real(wp), intent(in) :: normal(2)              !! unit normal into the material side [-]
    real(wp), intent(in), optional :: velocity(2)  !! prescribed velocity [m/s]
    type(wall_cfg_t) :: w
    w%point = point
    w%normal = normal
    w%contact_id = CONTACT_FRICTIONLESS
    if (present(velocity)) w%velocity = velocity
    cfg%walls = [cfg%walls, w]
  end subroutine scene_add_wall
end module mpm_scene_builder
