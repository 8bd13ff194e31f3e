!> The background grid: square cells, node-based fields, and its placement and growth.
! SPDX-License-Identifier: MIT
!
! Node (i, j), i = 0..nx-1, j = 0..ny-1, is at origin + h*(i, j) and has the 1-based id
! n = 1 + i + nx*j. The grid carries no state from one step to the next (every step maps the
! particles afresh), so it can be moved or enlarged between steps at no cost but allocation.
module mpm_grid
  use mpm_kinds, only: wp, i8
  implicit none
  private
  public :: grid_t, grid_init, grid_node_id, grid_node_x, grid_grow, grid_memory_bytes

  !> Node fields of a square-cell grid.
  type :: grid_t
    real(wp) :: origin(2) = 0.0_wp       !! position of node (0, 0) [m]
    real(wp) :: h = 0.0_wp               !! cell size [m]
    real(wp) :: inv_h = 0.0_wp           !! 1 / h [1/m]
    integer :: nx = 0, ny = 0            !! nodes along x and y
    integer :: nn = 0                    !! nx * ny
    logical :: fixed = .false.           !! bounds given by the user: never grown
    real(wp), allocatable :: mass(:)     !! nodal mass [kg per unit depth]
    real(wp), allocatable :: mom(:,:)    !! nodal momentum (2, nn) [kg m/s]
    real(wp), allocatable :: force(:,:)  !! nodal force (2, nn) [N]
    real(wp), allocatable :: vel(:,:)    !! nodal velocity after the update (2, nn) [m/s]
    real(wp), allocatable :: dvel(:,:)   !! velocity change over the step (2, nn) [m/s]
    real(wp), allocatable :: gap(:,:)    !! (nwall, nn) distance of the nearest material [m]
    integer, allocatable :: active(:)    !! ids of nodes with mass this step
    integer :: nactive = 0               !! number of active nodes
  end type grid_t

contains

  !> Allocate a grid whose nodes span [lower, upper] (rounded outward to whole cells),
  !! with a node lattice passing through `anchor`.
  subroutine grid_init(g, lower, upper, h, anchor, nwall)
    type(grid_t), intent(inout) :: g      !! the grid
    real(wp), intent(in) :: lower(2)      !! lower corner to cover [m]
    real(wp), intent(in) :: upper(2)      !! upper corner to cover [m]
    real(wp), intent(in) :: h             !! cell size [m]
    real(wp), intent(in) :: anchor(2)     !! a point that must be a node [m]
    integer, intent(in) :: nwall          !! number of walls (gap field rows)
    integer :: i0(2), i1(2)
    g%h = h
    g%inv_h = 1.0_wp/h
    i0 = floor((lower - anchor)*g%inv_h + 1.0e-9_wp)
    i1 = ceiling((upper - anchor)*g%inv_h - 1.0e-9_wp)
    g%origin = anchor + real(i0, wp)*h
    g%nx = max(i1(1) - i0(1) + 1, 2)
    g%ny = max(i1(2) - i0(2) + 1, 2)
    call grid_allocate(g, nwall)
  end subroutine grid_init

  !> (Re)allocate the node fields for the current nx, ny.
  subroutine grid_allocate(g, nwall)
    type(grid_t), intent(inout) :: g      !! the grid
    integer, intent(in) :: nwall          !! number of walls
    g%nn = g%nx*g%ny
    if (allocated(g%mass)) deallocate(g%mass, g%mom, g%force, g%vel, g%dvel, g%gap, g%active)
    allocate(g%mass(g%nn), g%mom(2, g%nn), g%force(2, g%nn), g%vel(2, g%nn), g%dvel(2, g%nn))
    allocate(g%gap(max(nwall, 1), g%nn), g%active(g%nn))
    g%mass = 0.0_wp
    g%mom = 0.0_wp
    g%force = 0.0_wp
    g%vel = 0.0_wp
    g%dvel = 0.0_wp
    g%gap = huge(1.0_wp)
    g%nactive = 0
  end subroutine grid_allocate

  !> Enlarge the grid by whole cells on each side: add(1:2) at the low x/y side,
  !! add(3:4) at the high x/y side. Node positions of the old grid stay nodes.
  subroutine grid_grow(g, add, nwall)
    type(grid_t), intent(inout) :: g      !! the grid
    integer, intent(in) :: add(4)         !! cells to add: low x, low y, high x, high y
    integer, intent(in) :: nwall          !! number of walls
    g%origin = g%origin - real(add(1:2), wp)*g%h
    g%nx = g%nx + add(1) + add(3)
    g%ny = g%ny + add(2) + add(4)
    call grid_allocate(g, nwall)
  end subroutine grid_grow

  !> 1-based id of node (i, j).
  pure elemental integer function grid_node_id(nx, i, j) result(n)
    integer, intent(in) :: nx             !! nodes along x
    integer, intent(in) :: i, j           !! node indices (0-based)
    n = 1 + i + nx*j
  end function grid_node_id

  !> Position of the node with 1-based id n [m].
  pure function grid_node_x(g, n) result(x)
    type(grid_t), intent(in) :: g         !! the grid
    integer, intent(in) :: n              !! node id
    real(wp) :: x(2)
    x(1) = g%origin(1) + g%h*real(mod(n - 1, g%nx), wp)
    x(2) = g%origin(2) + g%h*real((n - 1)/g%nx, wp)
  end function grid_node_x

  !> Memory held by the grid fields [bytes].
  pure function grid_memory_bytes(g, nwall) result(b)
    type(grid_t), intent(in) :: g         !! the grid
    integer, intent(in) :: nwall          !! number of walls
    integer(i8) :: b
    b = int(g%nx, i8)*int(g%ny, i8)*(8_i8*(9_i8 + int(max(nwall, 1), i8)) + 4_i8)
  end function grid_memory_bytes
end module mpm_grid
