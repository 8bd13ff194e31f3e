!> The background grid: square cells, node-based fields, and its placement and growth; the
!! tiles that bound the region holding material, and the per-thread scatter buffers.
! SPDX-License-Identifier: MIT
!
! Node (i, j), i = 0..nx-1, j = 0..ny-1, is at origin + h*(i, j) and has the 1-based id
! n = 1 + i + nx*j. The grid carries no state from one step to the next (every step maps the
! particles afresh), so it can be moved or enlarged between steps at no cost but allocation.
!
! Tiles: squares of ts x ts nodes (ts a power of two), tile (tx, ty) = nodes
! tx*ts..tx*ts+ts-1 by ty*ts..ty*ts+ts-1, id 1 + tx + ntx*ty. A particle whose block's
! lower-left node lies in tile (tx, ty) writes only to tiles tx..tx+1 by ty..ty+1 while its
! block width nb <= ts + 1. The live tiles are those; mass, mom and force are zero outside
! them, and vel, dvel are set on all of their nodes by the grid update, so a step resets and
! visits the live tiles only, never the whole grid. Runs of live tiles in a tile row are kept
! as spans (node rectangles), so that grid loops run over long rows. Tiles of equal parity
! (tx mod 2, ty mod 2) are written by disjoint particle sets: the four colours of the
! deterministic scatter.
module mpm_grid
  use mpm_kinds, only: wp, i8
  implicit none
  private
  public :: grid_t, grid_init, grid_node_id, grid_node_x, grid_grow, grid_memory_bytes
  public :: grid_set_tiles, grid_clear_live, grid_span, grid_thread_buffers

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
    integer :: nactive = 0               !! nodes with mass above mass_cut this step
    real(wp) :: mass_cut = 0.0_wp        !! active-node cut-off, 1e-12 of the largest mass [kg/m]
    ! tiles
    integer :: ts = 0                    !! tile side [nodes], a power of two (0: not set)
    integer :: ts_shift = 0              !! log2(ts)
    integer :: ntx = 0, nty = 0          !! tiles along x and y
    integer :: nspan = 0                 !! spans of live tiles
    integer :: stamp = 0                 !! binning pass number (marks occupied tiles)
    integer, allocatable :: occupied(:)  !! stamp of the last pass that binned a particle here
    integer, allocatable :: span(:,:)    !! (i0, i1, j0, j1) node ranges of the spans, ascending
    integer, allocatable :: tile_start(:) !! (ntiles + 1) first sorted particle of each tile
    integer, allocatable :: colour_tiles(:) !! occupied tiles grouped by band and colour
    integer :: ngroup = 0                !! groups (band, colour) of colour_tiles
    integer, allocatable :: group_start(:) !! group i holds colour_tiles(group_start(i):..(i+1)-1)
    integer, allocatable :: group_pos(:) !! work array of the grouping (ngroup)
    real(wp), allocatable :: colour_sum(:,:) !! (2, ntiles) partial sums per listed tile
    real(wp), allocatable :: span_sum(:,:) !! partial sums per span (nsum, ntiles)
    ! scatter buffers of threads 1..nbuf (thread 0 scatters into mass, mom, force)
    integer :: nbuf = 0                  !! buffers allocated
    real(wp), allocatable :: buf_mass(:,:)     !! (nn, nbuf) [kg/m]
    real(wp), allocatable :: buf_mom(:,:,:)    !! (2, nn, nbuf) [kg/s]
    real(wp), allocatable :: buf_force(:,:,:)  !! (2, nn, nbuf) [N/m]
  end type grid_t

  integer, parameter :: tile_side_min = 4      !! smallest tile side [nodes]

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

  !> (Re)allocate the node fields for the current nx, ny; all zero, no live tiles.
  subroutine grid_allocate(g, nwall)
    type(grid_t), intent(inout) :: g      !! the grid
    integer, intent(in) :: nwall          !! number of walls
    integer :: nbuf
    g%nn = g%nx*g%ny
    if (allocated(g%mass)) deallocate(g%mass, g%mom, g%force, g%vel, g%dvel, g%gap)
    allocate(g%mass(g%nn), g%mom(2, g%nn), g%force(2, g%nn), g%vel(2, g%nn), g%dvel(2, g%nn))
    allocate(g%gap(max(nwall, 1), g%nn))
    g%mass = 0.0_wp
    g%mom = 0.0_wp
    g%force = 0.0_wp
    g%vel = 0.0_wp
    g%dvel = 0.0_wp
    g%gap = huge(1.0_wp)
    g%nactive = 0
    g%nspan = 0
    call tile_allocate(g, max(g%ts, tile_side_min))
    nbuf = g%nbuf
    g%nbuf = 0
    call grid_thread_buffers(g, nbuf + 1)
  end subroutine grid_allocate

  !> Tile arrays for tile side ts (the node fields must be zero: no live tiles).
  subroutine tile_allocate(g, ts)
    type(grid_t), intent(inout) :: g      !! the grid
    integer, intent(in) :: ts             !! tile side, a power of two [nodes]
    integer :: ntiles
    g%ts = ts
    g%ts_shift = 0
    do while (ishft(1, g%ts_shift) < ts)
      g%ts_shift = g%ts_shift + 1
    end do
    g%ntx = (g%nx + ts - 1)/ts
    g%nty = (g%ny + ts - 1)/ts
    ntiles = g%ntx*g%nty
    if (allocated(g%occupied)) deallocate(g%occupied, g%span, g%tile_start, g%colour_tiles, &
                                          g%colour_sum)
    if (allocated(g%span_sum)) deallocate(g%span_sum)
    allocate(g%occupied(ntiles), g%span(4, ntiles), g%tile_start(ntiles + 1), &
             g%colour_tiles(ntiles), g%colour_sum(2, ntiles))
    g%occupied = 0
    g%stamp = 0
    g%nspan = 0
    g%tile_start = 1
    g%ngroup = 0
  end subroutine tile_allocate

  !> Use tiles of side ts (a power of two >= 4); a change first clears the live region.
  subroutine grid_set_tiles(g, ts, par)
    type(grid_t), intent(inout) :: g      !! the grid
    integer, intent(in) :: ts             !! tile side [nodes]
    logical, intent(in) :: par            !! run in parallel
    if (ts == g%ts) return
    call grid_clear_live(g, par)
    call tile_allocate(g, ts)
  end subroutine grid_set_tiles

  !> Zero mass, momentum and force on the live tiles: afterwards they are zero everywhere.
  !! No live tiles remain. (Velocity and its change need no clearing: the grid update sets them
  !! on every node of the live tiles, and nothing reads them elsewhere but with weight 0.)
  subroutine grid_clear_live(g, par)
    type(grid_t), intent(inout) :: g      !! the grid
    logical, intent(in) :: par            !! run in parallel
    integer :: k, j, n0, n1
    !$omp parallel do default(none) schedule(static) shared(g) private(k, j, n0, n1) if(par)
    do k = 1, g%nspan
      do j = g%span(3, k), g%span(4, k)
        n0 = 1 + g%span(1, k) + g%nx*j
        n1 = 1 + g%span(2, k) + g%nx*j
        g%mass(n0:n1) = 0.0_wp
        g%mom(:, n0:n1) = 0.0_wp
        g%force(:, n0:n1) = 0.0_wp
      end do
    end do
    !$omp end parallel do
    g%nspan = 0
  end subroutine grid_clear_live

  !> Node ranges (0-based columns i0..i1, rows j0..j1) of live span k.
  pure subroutine grid_span(g, k, i0, i1, j0, j1)
    type(grid_t), intent(in) :: g         !! the grid
    integer, intent(in) :: k              !! span index
    integer, intent(out) :: i0, i1        !! first and last node column [-]
    integer, intent(out) :: j0, j1        !! first and last node row [-]
    i0 = g%span(1, k)
    i1 = g%span(2, k)
    j0 = g%span(3, k)
    j1 = g%span(4, k)
  end subroutine grid_span

  !> Make sure threads 1..nthreads-1 have zeroed scatter buffers (no-op when they exist).
  subroutine grid_thread_buffers(g, nthreads)
    type(grid_t), intent(inout) :: g      !! the grid
    integer, intent(in) :: nthreads       !! threads that will scatter
    if (nthreads - 1 <= g%nbuf) return
    if (allocated(g%buf_mass)) deallocate(g%buf_mass, g%buf_mom, g%buf_force)
    g%nbuf = nthreads - 1
    allocate(g%buf_mass(g%nn, g%nbuf), g%buf_mom(2, g%nn, g%nbuf), &
             g%buf_force(2, g%nn, g%nbuf))
    g%buf_mass = 0.0_wp
    g%buf_mom = 0.0_wp
    g%buf_force = 0.0_wp
  end subroutine grid_thread_buffers

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

  !> Memory held by the grid [bytes]: per node 9 reals of fields, nwall gaps, 5 reals per
  !! extra thread buffer; per tile 7 integers, 2 reals and the partial sums.
  pure function grid_memory_bytes(g, nwall) result(b)
    type(grid_t), intent(in) :: g         !! the grid
    integer, intent(in) :: nwall          !! number of walls
    integer(i8) :: b
    b = int(g%nx, i8)*int(g%ny, i8)*(8_i8*(9_i8 + int(max(nwall, 1), i8) + 5_i8*int(g%nbuf, i8))) &
        + int(g%ntx, i8)*int(g%nty, i8)*44_i8
    if (allocated(g%span_sum)) b = b + 8_i8*size(g%span_sum, kind=i8)
  end function grid_memory_bytes
end module mpm_grid
