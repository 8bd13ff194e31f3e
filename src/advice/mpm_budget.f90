!> What a case will cost, estimated from the input before anything is allocated: particles,
!! grid nodes (with the room a fitted grid takes to grow), memory by part, and the check of the
!! memory against what the machine has available (refused with EXIT_INPUT when it does not fit).
! SPDX-License-Identifier: MIT
!
! The byte counts are those of the allocations (docs/performance.md, "Memory per particle"):
! particles_memory_bytes (23 reals and 6 integers per particle, 2 reals per corner), twice (the
! driver keeps a copy as the last good state); the basis cache of step 1 (24 nb^2 + 8 bytes per
! particle) and its work arrays (8); grid_memory_bytes (72 per node and velocity field);
! buffers_memory_bytes (40 per node, field and thread beyond the first); with several fields
! (bodies in contact) the field of each particle and corner and the particle list (8 per
! particle, 4 per corner) and the contact node map (4 per node); tiles_memory_bytes (44 bytes
! and the span sums per tile of 16 nodes); the snapshot writer's temporaries (corners, quads, F,
! columns: 128 per particle), with volumetric = 'fbar' or 'fbarwall' mpm_fbar's work arrays (80
! bytes per particle, 16 per node; 'fbarwall' 8 more per particle), the wall contact's work (per
! wall that is not a mirror plane: CPDI2 48 bytes per corner, the other bases 8 per particle),
! and a fixed 32 MiB for the program and its libraries. Counts are reals, so that a length typed
! in the wrong unit cannot overflow an integer.
module mpm_budget
  use mpm_kinds, only: wp
  use mpm_constants, only: EXIT_INPUT, SHAPE_RING, SECTOR_FULL, SECTOR_HALF, &
                           SECTOR_QUARTER, BASIS_CPDI2, VOLUMETRIC_FBAR, &
                           VOLUMETRIC_FBARWALL, CONTACT_SLIP
  use mpm_config, only: config_t
  use mpm_bodies, only: body_box, body_estimate, body_fields, has_sector
  use mpm_particles, only: basis_reach, basis_block
  use mpm_units, only: advice_units
  use mpm_strings, only: itoa, sci
  implicit none
  private
  public :: budget_t, budget_estimate, budget_check, budget_threads, budget_max_nodes, bytes_text
  public :: contact_fields

  real(wp), parameter :: base_bytes = 32.0_wp*1048576.0_wp  !! program, runtime, HDF5 [bytes]
  real(wp), parameter :: max_index = 2147483647.0_wp       !! largest default integer [-]

  !> The estimate of a case.
  type :: budget_t
    real(wp) :: particles = 0.0_wp         !! particles [-]
    real(wp) :: corners = 0.0_wp           !! domain corners [-]
    real(wp) :: nx = 0.0_wp, ny = 0.0_wp   !! grid nodes along x and y, growth included [-]
    real(wp) :: nodes = 0.0_wp             !! nx * ny [-]
    real(wp) :: extent(2) = 0.0_wp         !! extent of the grid at t = 0 [m]
    integer :: nb = 3                      !! block width of the basis [nodes]
    integer :: threads = 1                 !! threads that scatter [-]
    integer :: nwall = 0                   !! walls, mirror planes included [-]
    integer :: nf = 1                      !! velocity fields per node (contact_fields) [-]
    real(wp) :: particle_bytes = 0.0_wp    !! particles, their good-state copy, basis cache,
                                           !! work arrays, output temporaries [bytes]
    real(wp) :: grid_bytes = 0.0_wp        !! grid fields, thread buffers, tiles [bytes]
    real(wp) :: buffer_bytes = 0.0_wp      !! the thread buffers' part of grid_bytes [bytes]
    real(wp) :: total = 0.0_wp             !! everything, with the fixed base [bytes]
  end type budget_t

contains

  !> Estimate particles, nodes and memory of a validated case for `threads` threads.
  pure function budget_estimate(cfg, threads) result(b)
    type(config_t), intent(in) :: cfg      !! the case (validated)
    integer, intent(in) :: threads         !! threads of the run (>= 1)
    type(budget_t) :: b
    integer :: ib, nmirror, sector
    real(wp) :: lo(2), hi(2), blo(2), bhi(2), h, ext, ext_max, np, nc, margin, grow, ncw
    h = cfg%grid%h
    ext_max = 0.0_wp
    lo = huge(1.0_wp)
    hi = -huge(1.0_wp)
    sector = SECTOR_FULL
    do ib = 1, size(cfg%bodies)
      call body_estimate(cfg%bodies(ib), np, nc, ext)
      b%particles = b%particles + np
      b%corners = b%corners + nc
      ext_max = max(ext_max, ext)
      call body_box(cfg%bodies(ib), blo, bhi)
      lo = min(lo, blo)
      hi = max(hi, bhi)
      if (has_sector(cfg%bodies(ib)%shape_id)) sector = max(sector, cfg%bodies(ib)%sector_id)
    end do
    b%nb = basis_block(cfg%solver%basis_id, ext_max, h)
    nmirror = 0
    if (sector == SECTOR_HALF) nmirror = 1
    if (sector == SECTOR_QUARTER) nmirror = 2
    b%nwall = size(cfg%walls) + nmirror
    b%threads = max(threads, 1)
    if (cfg%grid%fitted) then               ! mpm_setup: the corners plus 2 h (and a half size)
      margin = 2.0_wp*h + basis_reach(cfg%solver%basis_id, 0.5_wp*ext_max)
      lo = lo - margin
      hi = hi + margin
    else
      lo = cfg%grid%lower
      hi = cfg%grid%upper
    end if
    b%extent = hi - lo
    b%nx = aint(min(b%extent(1)/h, 1.0e30_wp)) + 3.0_wp    ! whole cells, rounded outward
    b%ny = aint(min(b%extent(2)/h, 1.0e30_wp)) + 3.0_wp
    if (cfg%grid%fitted) then               ! room for one growth (mpm_weights: 2 + n/10 a side)
      grow = 2.0_wp*(2.0_wp + aint(max(b%nx, b%ny)/10.0_wp))
      b%nx = b%nx + grow
      b%ny = b%ny + grow
    end if
    b%nodes = b%nx*b%ny
    b%particle_bytes = 2.0_wp*(b%particles*(23.0_wp*8.0_wp + 6.0_wp*4.0_wp) + &
                               b%corners*16.0_wp) &
                       + b%particles*(24.0_wp*real(b%nb, wp)**2 + 8.0_wp + 8.0_wp + 128.0_wp)
    b%nf = contact_fields(cfg)
    b%buffer_bytes = b%nodes*40.0_wp*real(b%nf*(b%threads - 1), wp)
    b%grid_bytes = b%nodes*(72.0_wp*real(b%nf, wp) &
                            + (44.0_wp + 8.0_wp*real(1 + 2*b%nwall, wp))/16.0_wp) + b%buffer_bytes
    if (cfg%solver%volumetric_id >= VOLUMETRIC_FBAR) then   ! mpm_fbar's work arrays
      b%particle_bytes = b%particle_bytes + b%particles*80.0_wp
      b%grid_bytes = b%grid_bytes + b%nodes*16.0_wp
      if (cfg%solver%volumetric_id == VOLUMETRIC_FBARWALL) &   ! columns through the wall
        b%particle_bytes = b%particle_bytes + b%particles*8.0_wp
    end if
    if (b%nf > 1) then                      ! mpm_body_contact: fields of the particles and
      b%particle_bytes = b%particle_bytes + 8.0_wp*b%particles + 4.0_wp*b%corners  ! corners,
      b%grid_bytes = b%grid_bytes + 4.0_wp*b%nodes       ! the contact node of each node
      if (any(cfg%bodies%self_contact)) b%particle_bytes = b%particle_bytes + &
                                                   4.0_wp*b%particles  ! mpm_self_contact: bonds
    end if
    ! the wall contact's work per wall that is not a mirror plane (mpm_surface_contact,
    ! mpm_surface_curve): CPDI2 each corner's gap and its control point's, boundary neighbours
    ! and list, the neighbours that shift its control point, and mass share (48 bytes), the
    ! other bases each particle's deepest corner gap (8)
    ncw = real(count(cfg%walls%contact_id /= CONTACT_SLIP), wp)
    if (cfg%solver%basis_id == BASIS_CPDI2) then
      b%particle_bytes = b%particle_bytes + ncw*48.0_wp*b%corners
    else
      b%particle_bytes = b%particle_bytes + ncw*8.0_wp*b%particles
    end if
    b%total = b%particle_bytes + b%grid_bytes + base_bytes
  end function budget_estimate

  !> Velocity fields per grid node: one per body where there are several (each body its own
  !! velocity field, mpm_body_contact), and a second one for a ring with self_contact (its
  !! lower half, mpm_self_contact); 1 for one body without self-contact.
  pure integer function contact_fields(cfg) result(nf)
    type(config_t), intent(in) :: cfg      !! the case
    integer :: k
    nf = 0
    do k = 1, size(cfg%bodies)
      nf = nf + body_fields(cfg%bodies(k))
    end do
  end function contact_fields

  !> Refuse (stat = EXIT_INPUT) a case whose estimate exceeds the memory available (`known`:
  !! a number was found) or whose particles or nodes overflow the integer indices; errmsg
  !! says both numbers and what to change.
  subroutine budget_check(cfg, b, available, source, known, stat, errmsg)
    type(config_t), intent(in) :: cfg      !! the case
    type(budget_t), intent(in) :: b        !! its estimate
    real(wp), intent(in) :: available      !! memory available [bytes]
    character(len=*), intent(in) :: source !! where that number comes from
    logical, intent(in) :: known           !! available is known
    integer, intent(out) :: stat           !! 0 or EXIT_INPUT
    character(len=:), allocatable, intent(out) :: errmsg  !! what is too big, what to change
    character(len=:), allocatable :: what, hints
    stat = 0
    errmsg = ''
    if (b%particles > max_index .or. b%corners > max_index .or. &
        b%nodes*real(b%nf, wp) > max_index) then
      what = 'more particles or grid nodes than this program can index (2^31 - 1)'
    else if (known .and. b%total > available) then
      what = 'about '//bytes_text(b%total)//' of memory, more than the '// &
             bytes_text(available)//' available ('//source//')'
    else
      return
    end if
    stat = EXIT_INPUT
    errmsg = trim(cfg%file)//': the case needs '//what//': '//count_text(b%particles)// &
      ' particles ('//bytes_text(b%particle_bytes)//'), a grid of '//count_text(b%nx)// &
      ' x '//count_text(b%ny)//' nodes over '//len_text(b%extent(1))//' x '// &
      len_text(b%extent(2))//' m at h = '//len_text(cfg%grid%h)//' m ('// &
      bytes_text(b%grid_bytes)
    if (cfg%grid%fitted) errmsg = errmsg//', with room to grow'
    errmsg = errmsg//').'
    if (b%buffer_bytes > 0.5_wp*b%grid_bytes .and. b%buffer_bytes > b%particle_bytes) then
      errmsg = errmsg//' Change: fewer &run threads (the '//itoa(b%threads)//' threads'' '// &
        'scatter buffers take '//bytes_text(b%buffer_bytes)//' of the grid''s share, 40 B '// &
        'per node for each thread beyond the first; threads = 0 takes one per free core)'
    else if (b%grid_bytes >= b%particle_bytes) then
      errmsg = errmsg//' Change: a larger &grid h (the nodes grow as 1/h^2), the size of '// &
        'the bodies '// &
        '(&body r_inner, r_outer, size, center: lengths are in metres), or give &grid '// &
        'lower, upper closer around the material'
    else
      errmsg = errmsg//' Change: the particles (&body n_thick, n_circ; n_x, n_y of a '// &
        'rectangle) or the size of the bodies (&body r_inner, r_outer, size: in metres)'
    end if
    call advice_units(cfg, hints)
    if (len(hints) > 0) errmsg = errmsg//new_line('a')//hints
  end subroutine budget_check

  !> Threads a run of the case will use: &run threads, or the OpenMP default.
  function budget_threads(cfg) result(n)
    !$ use omp_lib, only: omp_get_max_threads
    type(config_t), intent(in) :: cfg      !! the case
    integer :: n
    n = 1
    !$ n = omp_get_max_threads()
    if (cfg%run%threads > 0) n = cfg%run%threads
  end function budget_threads

  !> The most grid nodes the memory left beside the particles can hold (for the growth of a
  !! fitted grid during the run; huge when the memory available is not known) [-].
  pure function budget_max_nodes(b, available, known) result(n)
    type(budget_t), intent(in) :: b        !! the estimate of the case
    real(wp), intent(in) :: available      !! memory available [bytes]
    logical, intent(in) :: known           !! available is known
    real(wp) :: n
    n = max_index/real(b%nf, wp)            ! every field of every node must be indexable
    if (known .and. b%nodes > 0.0_wp) &
      n = min(n, max(available - b%particle_bytes - base_bytes, 0.0_wp)/(b%grid_bytes/b%nodes))
  end function budget_max_nodes

  !> Bytes as text in MiB or GiB ('1.50 GiB').
  pure function bytes_text(bytes) result(text)
    real(wp), intent(in) :: bytes          !! [bytes]
    character(len=:), allocatable :: text
    character(len=32) :: buf
    if (bytes >= 1.0e18_wp) then
      buf = sci(bytes/1073741824.0_wp, 2)//' GiB'
    else if (bytes >= 1073741824.0_wp) then
      write(buf, '(f12.2,a)') bytes/1073741824.0_wp, ' GiB'
    else
      write(buf, '(f12.1,a)') bytes/1048576.0_wp, ' MiB'
    end if
    text = trim(adjustl(buf))
  end function bytes_text

  !> A count held as a real, as an integer text when it fits ('123456', else '1.23E+15').
  pure function count_text(x) result(text)
    real(wp), intent(in) :: x              !! count [-]
    character(len=:), allocatable :: text
    character(len=32) :: buf
    if (x < 1.0e15_wp) then
      write(buf, '(i0)') nint(x, kind=selected_int_kind(18))
    else
      buf = sci(x, 2)
    end if
    text = trim(adjustl(buf))
  end function count_text

  !> A length with 4 significant digits [m].
  pure function len_text(x) result(text)
    real(wp), intent(in) :: x              !! [m]
    character(len=:), allocatable :: text
    text = sci(x, 3)
  end function len_text
end module mpm_budget
