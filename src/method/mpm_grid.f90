!> The background grid: square cells, node-based fields, and its placement and growth; the
!! per-thread scatter buffers (node-sized). The tiles that bound the live region are mpm_tiles.
! SPDX-License-Identifier: MIT
!
! Node (i, j), i = 0..nx-1, j = 0..ny-1, is at origin + h*(i, j) and has the 1-based id
! n = 1 + i + nx*j. The grid carries no state from one step to the next (every step maps the
! particles afresh), so it can be moved or enlarged between steps at no cost but allocation.
!
! The node fields mass, mom and force are zero outside the live tiles (mpm_tiles).
!
! Multi-field contact (mpm_body_contact): with nf > 1 velocity fields every node carries nf
! copies of its fields, one per contact field (a body, or part of one), field f of node n at
! n + (f - 1) nn: the arrays hold nn * nf nodes. With one field (one body) nothing changes.
module mpm_grid
  use mpm_kinds, only: wp, i8
  implicit none
  private
  public :: grid_t, grid_init, grid_node_id, grid_node_x, grid_grow, grid_memory_bytes
  public :: buffers_t, grid_thread_buffers, buffers_memory_bytes, grid_write_placement, &
            grid_read_placement

  !> Node fields of a square-cell grid.
  type :: grid_t
    real(wp) :: origin(2) = 0.0_wp       !! position of node (0, 0) [m]
    real(wp) :: h = 0.0_wp               !! cell size [m]
    real(wp) :: inv_h = 0.0_wp           !! 1 / h [1/m]
    integer :: nx = 0, ny = 0            !! nodes along x and y
    integer :: nn = 0                    !! nx * ny
    integer :: nf = 1                    !! velocity fields per node (mpm_body_contact)
    logical :: fixed = .false.           !! bounds given by the user: never grown
    real(wp), allocatable :: mass(:)     !! nodal mass (nn nf) [kg per unit depth]
    real(wp), allocatable :: mom(:,:)    !! nodal momentum (2, nn nf) [kg m/s]
    real(wp), allocatable :: force(:,:)  !! nodal force (2, nn nf) [N]
    real(wp), allocatable :: vel(:,:)    !! nodal velocity after the update (2, nn nf) [m/s]
    real(wp), allocatable :: dvel(:,:)   !! velocity change over the step (2, nn nf) [m/s]
    integer :: nactive = 0               !! nodes with mass above mass_cut this step
    real(wp) :: mass_cut = 0.0_wp        !! active-node cut-off, 1e-12 of the largest mass [kg/m]
  end type grid_t

  !> Scatter buffers of threads 1..nbuf (thread 0 scatters into the grid's mass, mom, force).
  type :: buffers_t
    integer :: nbuf = 0                  !! buffers allocated
    integer :: nn = 0                    !! nodes per buffer (the grid's when allocated)
    real(wp), allocatable :: buf_mass(:,:)     !! (nn, nbuf) [kg/m]
    real(wp), allocatable :: buf_mom(:,:,:)    !! (2, nn, nbuf) [kg/s]
    real(wp), allocatable :: buf_force(:,:,:)  !! (2, nn, nbuf) [N/m]
  end type buffers_t

contains

  !> Allocate a grid whose nodes span [lower, upper] (rounded outward to whole cells),
  !! with a node lattice passing through `anchor`, and nf velocity fields (default 1).
  subroutine grid_init(g, lower, upper, h, anchor, nf)
    type(grid_t), intent(inout) :: g      !! the grid
    real(wp), intent(in) :: lower(2)      !! lower corner to cover [m]
    real(wp), intent(in) :: upper(2)      !! upper corner to cover [m]
    real(wp), intent(in) :: h             !! cell size [m]
    real(wp), intent(in) :: anchor(2)     !! a point that must be a node [m]
    integer, intent(in), optional :: nf   !! velocity fields per node
    integer :: i0(2), i1(2)
    g%nf = 1
    if (present(nf)) g%nf = max(nf, 1)
    g%h = h
    g%inv_h = 1.0_wp/h
    i0 = floor((lower - anchor)*g%inv_h + 1.0e-9_wp)
    i1 = ceiling((upper - anchor)*g%inv_h - 1.0e-9_wp)
    g%origin = anchor + real(i0, wp)*h
    g%nx = max(i1(1) - i0(1) + 1, 2)
    g%ny = max(i1(2) - i0(2) + 1, 2)
    call grid_allocate(g)
  end subroutine grid_init

  !> (Re)allocate the node fields for the current nx, ny and nf; all zero.
  subroutine grid_allocate(g)
    type(grid_t), intent(inout) :: g      !! the grid
    integer :: n
    g%nn = g%nx*g%ny
    n = g%nn*g%nf
    if (allocated(g%mass)) deallocate(g%mass, g%mom, g%force, g%vel, g%dvel)
    allocate(g%mass(n), g%mom(2, n), g%force(2, n), g%vel(2, n), g%dvel(2, n))
    g%mass = 0.0_wp
    g%mom = 0.0_wp
    g%force = 0.0_wp
    g%vel = 0.0_wp
    g%dvel = 0.0_wp
    g%nactive = 0
  end subroutine grid_allocate

  !> Make sure threads 1..nthreads-1 have zeroed scatter buffers of nn nodes (all fields: the
  !! grid's nn nf; no-op when they exist; a grid of another size gets new ones, as many as
  !! before at least).
  subroutine grid_thread_buffers(b, nn, nthreads)
    type(buffers_t), intent(inout) :: b   !! the buffers
    integer, intent(in) :: nn             !! nodes of the grid
    integer, intent(in) :: nthreads       !! threads that will scatter
    if (nthreads - 1 <= b%nbuf .and. (b%nn == nn .or. b%nbuf == 0)) return
    if (allocated(b%buf_mass)) deallocate(b%buf_mass, b%buf_mom, b%buf_force)
    b%nbuf = max(b%nbuf, nthreads - 1)
    b%nn = nn
    allocate(b%buf_mass(nn, b%nbuf), b%buf_mom(2, nn, b%nbuf), b%buf_force(2, nn, b%nbuf))
    b%buf_mass = 0.0_wp
    b%buf_mom = 0.0_wp
    b%buf_force = 0.0_wp
  end subroutine grid_thread_buffers

  !> Enlarge the grid by whole cells on each side: add(1:2) at the low x/y side,
  !! add(3:4) at the high x/y side. Node positions of the old grid stay nodes.
  subroutine grid_grow(g, add)
    type(grid_t), intent(inout) :: g      !! the grid
    integer, intent(in) :: add(4)         !! cells to add: low x, low y, high x, high y
    g%origin = g%origin - real(add(1:2), wp)*g%h
    g%nx = g%nx + add(1) + add(3)
    g%ny = g%ny + add(2) + add(4)
    call grid_allocate(g)
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

  !> Memory held by the grid's node fields [bytes]: per node and field 9 reals.
  pure function grid_memory_bytes(g) result(b)
    type(grid_t), intent(in) :: g         !! the grid
    integer(i8) :: b
    b = int(g%nx, i8)*int(g%ny, i8)*72_i8*int(g%nf, i8)
  end function grid_memory_bytes

  !> Memory held by the scatter buffers [bytes]: 5 reals per node and buffer.
  pure function buffers_memory_bytes(b) result(n)
    type(buffers_t), intent(in) :: b      !! the buffers
    integer(i8) :: n
    n = int(b%nn, i8)*8_i8*5_i8*int(b%nbuf, i8)
  end function buffers_memory_bytes

  !> Write the grid's placement (nodes along x and y, origin) to the open unformatted stream
  !! unit u (a checkpoint record; the grid may have grown during the run).
  subroutine grid_write_placement(g, u, stat, errmsg)
    type(grid_t), intent(in) :: g             !! the grid
    integer, intent(in) :: u                  !! unit, open for unformatted stream output
    integer, intent(out) :: stat              !! 0 or the iostat of the failed write
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    write(u, iostat=stat, iomsg=errmsg) g%nx, g%ny, g%origin
  end subroutine grid_write_placement

  !> Read a record of grid_write_placement and grow g (set up from the same input, so on the
  !! same lattice) to that placement.
  subroutine grid_read_placement(g, u, stat, errmsg)
    type(grid_t), intent(inout) :: g          !! the grid
    integer, intent(in) :: u                  !! unit, open for unformatted stream input
    integer, intent(out) :: stat              !! 0 or the iostat of the failed read
    character(len=*), intent(inout) :: errmsg !! the iomsg on failure
    integer :: nx, ny
    real(wp) :: origin(2)
    read(u, iostat=stat, iomsg=errmsg) nx, ny, origin
    if (stat /= 0) return
    call grid_grow(g, [nint((g%origin(1) - origin(1))/g%h), nint((g%origin(2) - origin(2))/g%h), &
                       0, 0])
    call grid_grow(g, [0, 0, nx - g%nx, ny - g%ny])
  end subroutine grid_read_placement
end module mpm_grid
