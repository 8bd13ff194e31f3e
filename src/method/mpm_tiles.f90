!> Binning of the particles into grid tiles: the live region of the grid (spans of tiles), and
!! the colour groups of the deterministic scatter (step 1 of docs/method.md).
! SPDX-License-Identifier: MIT
!
! Tiles: squares of ts x ts nodes (ts a power of two), tile (tx, ty) = nodes
! tx*ts..tx*ts+ts-1 by ty*ts..ty*ts+ts-1, id 1 + tx + ntx*ty. A particle whose block's
! lower-left node lies in tile (tx, ty) writes only to tiles tx..tx+1 by ty..ty+1 while its
! block width nb <= ts + 1. The live tiles are those; the grid's mass, mom and force are zero
! outside them, and vel, dvel are set on all of their nodes by the grid update, so a step
! resets and visits the live tiles only, never the whole grid. Runs of live tiles in a tile
! row are kept as spans (node rectangles), so that grid loops run over long rows. Tiles of
! equal parity (tx mod 2, ty mod 2) are written by disjoint particle sets: the four colours of
! the deterministic scatter.
module mpm_tiles
  use mpm_kinds, only: wp, i8
  use mpm_grid, only: grid_t
  implicit none
  private
  public :: tiles_t, tiles_init, tiles_bin, tiles_clear_live, tiles_span, tiles_memory_bytes

  integer, parameter :: tile_side_min = 4      !! smallest tile side [nodes]
  integer, parameter :: tile_side = 4          !! tile side of the threaded scatter: bounds
                                               !! the live region [nodes]
  integer, parameter :: tile_side_colour = 16  !! tile side of the deterministic colour sweep:
                                               !! long particle runs, little halo [nodes]

  !> Tiles of the grid, the live spans, and the colour groups of the deterministic sweep.
  type :: tiles_t
    integer :: nx = 0, ny = 0            !! nodes of the grid the tiles were made for
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
    real(wp), allocatable :: colour_sum(:,:) !! (3, ntiles) partial sums per listed tile
    real(wp), allocatable :: span_sum(:,:) !! partial sums per span (nsum, ntiles)
  end type tiles_t

contains

  !> Tiles of the smallest side for grid g (no live tiles: g's fields must be zero).
  subroutine tiles_init(tl, g)
    type(tiles_t), intent(inout) :: tl    !! tiles
    type(grid_t), intent(in) :: g         !! grid
    call tiles_allocate(tl, g, max(tl%ts, tile_side_min))
  end subroutine tiles_init

  !> Tile arrays for tile side ts on grid g (the node fields must be zero: no live tiles).
  subroutine tiles_allocate(tl, g, ts)
    type(tiles_t), intent(inout) :: tl    !! tiles
    type(grid_t), intent(in) :: g         !! grid
    integer, intent(in) :: ts             !! tile side, a power of two [nodes]
    integer :: ntiles
    tl%nx = g%nx
    tl%ny = g%ny
    tl%ts = ts
    tl%ts_shift = 0
    do while (ishft(1, tl%ts_shift) < ts)
      tl%ts_shift = tl%ts_shift + 1
    end do
    tl%ntx = (g%nx + ts - 1)/ts
    tl%nty = (g%ny + ts - 1)/ts
    ntiles = tl%ntx*tl%nty
    if (allocated(tl%occupied)) deallocate(tl%occupied, tl%span, tl%tile_start, &
                                           tl%colour_tiles, tl%colour_sum)
    if (allocated(tl%span_sum)) deallocate(tl%span_sum)
    allocate(tl%occupied(ntiles), tl%span(4, ntiles), tl%tile_start(ntiles + 1), &
             tl%colour_tiles(ntiles), tl%colour_sum(3, ntiles))
    tl%occupied = 0
    tl%stamp = 0
    tl%nspan = 0
    tl%tile_start = 1
    tl%ngroup = 0
  end subroutine tiles_allocate

  !> Bin the particles into grid tiles (by the lower-left node of their block): mark the
  !! occupied tiles, clear the previous live region, list the new live tiles, and for the
  !! deterministic scatter sort the particles by tile and group the tiles by colour. A grid
  !! that was re-allocated (grown: its fields are zero) gets new tiles.
  subroutine tiles_bin(tl, g, np, nb, blk, deterministic, band, nsum, par, tile, perm)
    type(tiles_t), intent(inout) :: tl     !! tiles
    type(grid_t), intent(inout) :: g       !! grid (the old live region is zeroed)
    integer, intent(in) :: np              !! particles
    integer, intent(in) :: nb              !! block width [nodes]
    integer, intent(in) :: blk(2, np)      !! lower-left node of each block (0-based)
    logical, intent(in) :: deterministic   !! sort and colour for the deterministic sweep
    integer, intent(in) :: band            !! particles per band of the deterministic sweep
    integer, intent(in) :: nsum            !! partial sums per span (span_sum rows)
    logical, intent(in) :: par             !! run in parallel
    integer, intent(out) :: tile(np)       !! tile of each particle
    integer, intent(inout) :: perm(np)     !! particles sorted by tile (deterministic)
    integer :: ts
    ! tiles must hold a block: nb <= ts + 1 (the colour sweep relies on it)
    ts = merge(tile_side_colour, tile_side, deterministic)
    do while (ts + 1 < nb)
      ts = 2*ts
    end do
    if (tl%nx /= g%nx .or. tl%ny /= g%ny) then
      call tiles_allocate(tl, g, max(tl%ts, tile_side_min))
    end if
    if (ts /= tl%ts) then                    ! a change first clears the live region
      call tiles_clear_live(tl, g, par)
      call tiles_allocate(tl, g, ts)
    end if
    if (tl%stamp == huge(1)) then
      tl%occupied = 0
      tl%stamp = 0
    end if
    tl%stamp = tl%stamp + 1
    call mark_tiles(np, tl%ts_shift, tl%ntx, tl%stamp, blk, tile, tl%occupied, par)
    call tiles_clear_live(tl, g, par)
    call list_live_tiles(tl, g)
    if (deterministic) call sort_by_tile(tl, np, band, tile, perm)
    if (.not. allocated(tl%span_sum)) allocate(tl%span_sum(nsum, size(tl%span, 2)))
  end subroutine tiles_bin

  !> Zero mass, momentum and force on the live tiles (every field): afterwards they are zero
  !! everywhere. No live tiles remain. (Velocity and its change need no clearing: the grid
  !! update sets them on every node of the live tiles, and nothing reads them elsewhere but
  !! with weight 0.)
  subroutine tiles_clear_live(tl, g, par)
    type(tiles_t), intent(inout) :: tl    !! tiles
    type(grid_t), intent(inout) :: g      !! grid
    logical, intent(in) :: par            !! run in parallel
    integer :: k, j, n0, n1, f, n
    !$omp parallel do default(none) schedule(static) shared(tl, g) private(k, j, n0, n1, f, n) &
    !$omp   if(par)
    do k = 1, tl%nspan
      do f = 0, g%nf - 1
        do j = tl%span(3, k), tl%span(4, k)
          n0 = 1 + tl%span(1, k) + g%nx*j + f*g%nn
          n1 = 1 + tl%span(2, k) + g%nx*j + f*g%nn
          do n = n0, n1                      ! (element by element: `mom(:, n0:n1) = 0` was a
            g%mass(n) = 0.0_wp               ! memset call per node)
            g%mom(1, n) = 0.0_wp
            g%mom(2, n) = 0.0_wp
            g%force(1, n) = 0.0_wp
            g%force(2, n) = 0.0_wp
          end do
        end do
      end do
    end do
    !$omp end parallel do
    tl%nspan = 0
  end subroutine tiles_clear_live

  !> Node ranges (0-based columns i0..i1, rows j0..j1) of live span k.
  pure subroutine tiles_span(tl, k, i0, i1, j0, j1)
    type(tiles_t), intent(in) :: tl       !! tiles
    integer, intent(in) :: k              !! span index
    integer, intent(out) :: i0, i1        !! first and last node column [-]
    integer, intent(out) :: j0, j1        !! first and last node row [-]
    i0 = tl%span(1, k)
    i1 = tl%span(2, k)
    j0 = tl%span(3, k)
    j1 = tl%span(4, k)
  end subroutine tiles_span

  !> Memory held by the tiles [bytes]: per tile 7 integers, 2 reals and the partial sums.
  pure function tiles_memory_bytes(tl) result(b)
    type(tiles_t), intent(in) :: tl       !! tiles
    integer(i8) :: b
    b = int(tl%ntx, i8)*int(tl%nty, i8)*44_i8
    if (allocated(tl%span_sum)) b = b + 8_i8*size(tl%span_sum, kind=i8)
  end function tiles_memory_bytes

  !> Tile of every particle's block, and the stamp on every occupied tile.
  subroutine mark_tiles(np, shift, ntx, stamp, blk, tile, occupied, par)
    integer, intent(in) :: np              !! particles
    integer, intent(in) :: shift           !! log2 of the tile side
    integer, intent(in) :: ntx             !! tiles along x
    integer, intent(in) :: stamp           !! this pass's mark
    integer, intent(in) :: blk(2, np)      !! lower-left node of each block (0-based)
    integer, intent(out) :: tile(np)       !! tile id of each particle
    integer, intent(inout) :: occupied(:)  !! stamp of the last pass binning into each tile
    logical, intent(in) :: par             !! run in parallel
    integer :: ip, t, down, nt, mark
    down = shift                           ! (private copies: the loop keeps them in registers)
    nt = ntx
    mark = stamp
    !$omp parallel do default(none) schedule(static) shared(np, blk, tile, occupied) &
    !$omp   firstprivate(down, nt, mark) private(ip, t) if(par)
    do ip = 1, np
      t = 1 + shiftr(blk(1, ip), down) + nt*shiftr(blk(2, ip), down)   ! = ishft(., -shift)
      tile(ip) = t
      !$omp atomic write
      occupied(t) = mark
    end do
    !$omp end parallel do
  end subroutine mark_tiles

  !> Live tiles: occupied tiles and their right, upper and upper-right neighbours (a block
  !! reaches at most one tile further in x and y), as spans of consecutive live tiles in each
  !! tile row, ascending.
  subroutine list_live_tiles(tl, g)
    type(tiles_t), intent(inout) :: tl     !! tiles
    type(grid_t), intent(in) :: g          !! grid (its size)
    integer :: tx, ty, t, k, st, first
    logical :: live
    st = tl%stamp
    k = 0
    do ty = 0, tl%nty - 1
      first = -1
      do tx = 0, tl%ntx
        live = .false.
        if (tx < tl%ntx) then
          t = 1 + tx + tl%ntx*ty
          live = tl%occupied(t) == st
          if (tx > 0) live = live .or. tl%occupied(t - 1) == st
          if (ty > 0) then
            live = live .or. tl%occupied(t - tl%ntx) == st
            if (tx > 0) live = live .or. tl%occupied(t - tl%ntx - 1) == st
          end if
        end if
        if (live .and. first < 0) first = tx
        if (.not. live .and. first >= 0) then          ! a span ends before tx
          k = k + 1
          tl%span(:, k) = [tl%ts*first, min(tl%ts*tx, g%nx) - 1, tl%ts*ty, &
                           min(tl%ts*(ty + 1), g%ny) - 1]
          first = -1
        end if
      end do
    end do
    tl%nspan = k
  end subroutine list_live_tiles

  !> Deterministic scatter: a stable counting sort of the particles by tile (perm), and the
  !! occupied tiles in groups (band, colour): a band holds the tiles whose first particle is
  !! among the same band consecutive particles, the colour is (tx mod 2, ty mod 2), and
  !! within a group the tiles follow their first particles. The sweeps take the groups in order,
  !! so that one band's particles and grid region stay in cache over its four colours.
  subroutine sort_by_tile(tl, np, band, tile, perm)
    type(tiles_t), intent(inout) :: tl     !! tiles
    integer, intent(in) :: np              !! particles
    integer, intent(in) :: band            !! particles per band
    integer, intent(in) :: tile(np)        !! tile of each particle
    integer, intent(out) :: perm(np)       !! particles sorted by tile
    integer :: ip, t, i, ntiles
    ntiles = tl%ntx*tl%nty
    tl%ngroup = 4*((np + band - 1)/band)
    if (allocated(tl%group_start)) then
      if (size(tl%group_pos) < tl%ngroup) deallocate(tl%group_start, tl%group_pos)
    end if
    if (.not. allocated(tl%group_start)) allocate(tl%group_start(tl%ngroup + 1), &
                                                  tl%group_pos(tl%ngroup))
    tl%tile_start = 0
    do ip = 1, np                      ! particles per tile (in tile_start(t + 1))
      tl%tile_start(tile(ip) + 1) = tl%tile_start(tile(ip) + 1) + 1
    end do
    tl%group_start = 0
    do ip = 1, np                      ! tiles per group; a listed tile's count < 0
      t = tile(ip)
      if (tl%tile_start(t + 1) <= 0) cycle
      i = tile_group(ip, t, tl%ntx, band)
      tl%group_start(i + 1) = tl%group_start(i + 1) + 1
      tl%tile_start(t + 1) = -tl%tile_start(t + 1)
    end do
    tl%group_start(1) = 1
    do i = 1, tl%ngroup
      tl%group_start(i + 1) = tl%group_start(i + 1) + tl%group_start(i)
    end do
    tl%group_pos = tl%group_start(1:tl%ngroup)
    do ip = 1, np                      ! the tiles, in the order of their first particle
      t = tile(ip)
      if (tl%tile_start(t + 1) >= 0) cycle
      i = tile_group(ip, t, tl%ntx, band)
      tl%colour_tiles(tl%group_pos(i)) = t
      tl%group_pos(i) = tl%group_pos(i) + 1
      tl%tile_start(t + 1) = -tl%tile_start(t + 1)
    end do
    tl%tile_start(1) = 1
    do t = 1, ntiles
      tl%tile_start(t + 1) = tl%tile_start(t + 1) + tl%tile_start(t)
    end do
    do ip = 1, np                      ! tile_start(t) runs to the start of tile t + 1
      perm(tl%tile_start(tile(ip))) = ip
      tl%tile_start(tile(ip)) = tl%tile_start(tile(ip)) + 1
    end do
    do t = ntiles, 1, -1
      tl%tile_start(t + 1) = tl%tile_start(t)
    end do
    tl%tile_start(1) = 1
  end subroutine sort_by_tile

  !> Group of tile t whose first particle is ip: 4 (band - 1) + colour, colour 1..4 =
  !! 1 + (tx mod 2) + 2 (ty mod 2).
  pure integer function tile_group(ip, t, ntx, band) result(i)
    integer, intent(in) :: ip              !! first particle of the tile
    integer, intent(in) :: t               !! tile id
    integer, intent(in) :: ntx             !! tiles along x
    integer, intent(in) :: band            !! particles per band
    i = 4*((ip - 1)/band) + 1 + mod(mod(t - 1, ntx), 2) + 2*mod((t - 1)/ntx, 2)
  end function tile_group
end module mpm_tiles
