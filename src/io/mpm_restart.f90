!> Checkpoints: the full state of a run in one binary file, written atomically, read back by
!! `tubempm --restart DIR`.
! SPDX-License-Identifier: MIT
!
! Layout (unformatted stream, native byte order): magic 'TUBEMPM-CKPT', format version, the
! resolved input text (length + characters), then the records each type writes itself: the grid
! placement (mpm_grid), the run's diagnostics (mpm_state: growths, extremes), the state
! (mpm_state: time and energies, then the walls (mpm_walls) and the particles (mpm_particles)),
! then the output positions (history rows and last row time, snapshot times and sizes, the next
! snapshot time, the contact times of `end_at_release`) and a trailing magic. This module lists
! no field of those types. It is written to `checkpoint.tmp`, flushed, closed and renamed to
! `checkpoint.bin`, so a crash while writing leaves the previous checkpoint intact.
module mpm_restart
  use mpm_kinds, only: wp, i8
  use mpm_state, only: sim_t, state_write, state_read, diag_write, diag_read
  use mpm_grid, only: grid_write_placement, grid_read_placement
  use mpm_sys, only: sys_rename
  use mpm_strings, only: itoa
  implicit none
  private
  public :: checkpoint_write, checkpoint_read, ckpt_extra_t

  character(len=12), parameter :: magic = 'TUBEMPM-CKPT'
  integer, parameter :: format_version = 5  !! 5: the contact's energy loss (2026-11-28)

  !> What the driver needs besides the simulation state to continue its outputs.
  type :: ckpt_extra_t
    integer :: history_rows = 0            !! rows in history.csv (after the header)
    real(wp) :: history_next = 0.0_wp      !! time of the next history row [s]
    real(wp) :: history_last = 0.0_wp      !! time of the last history row [s]
    real(wp) :: snapshot_next = 0.0_wp     !! time of the next snapshot [s]
    real(wp), allocatable :: snap_times(:) !! times of the snapshots written [s]
    integer, allocatable :: snap_np(:)     !! their particle counts
    integer, allocatable :: snap_nc(:)     !! their corner counts
    real(wp) :: wall_seconds = 0.0_wp      !! wall-clock time used before this checkpoint [s]
    real(wp) :: contact_first = -1.0_wp    !! first and last step in contact (mpm_release;
    real(wp) :: contact_last = -1.0_wp     !! < 0: none yet) [s]
  end type ckpt_extra_t

contains

  !> Write the checkpoint of s into dir/checkpoint.bin (atomically).
  subroutine checkpoint_write(dir, input_text, s, ex, stat, errmsg)
    character(len=*), intent(in) :: dir          !! output folder
    character(len=*), intent(in) :: input_text   !! resolved input (input.nml text)
    type(sim_t), intent(in) :: s                 !! simulation
    type(ckpt_extra_t), intent(in) :: ex         !! output positions
    integer, intent(out) :: stat                 !! 0, or non-zero on an I/O failure
    character(len=:), allocatable, intent(out) :: errmsg  !! the failure, naming the file
    integer :: u, k
    character(len=512) :: msg
    character(len=:), allocatable :: tmp, fin
    msg = ''
    tmp = dir//'/checkpoint.tmp'
    fin = dir//'/checkpoint.bin'
    errmsg = ''
    open(newunit=u, file=tmp, access='stream', form='unformatted', status='replace', &
         action='write', iostat=stat, iomsg=msg)
    if (stat /= 0) then
      errmsg = 'cannot open '//tmp//' for writing: '//trim(msg)
      return
    end if
    write(u, iostat=stat, iomsg=msg) magic, format_version, len(input_text), input_text
    if (stat == 0) call grid_write_placement(s%g, u, stat, msg)
    if (stat == 0) call diag_write(s%diag, u, stat, msg)
    if (stat == 0) call state_write(s%state_t, u, stat, msg)
    if (stat == 0) write(u, iostat=stat, iomsg=msg) ex%history_rows, ex%history_next, &
      ex%history_last, ex%snapshot_next, size(ex%snap_times), ex%snap_times, ex%snap_np, &
      ex%snap_nc, ex%wall_seconds, ex%contact_first, ex%contact_last, magic
    if (stat /= 0) then
      errmsg = 'cannot write '//tmp//': '//trim(msg)
      close(u, status='delete', iostat=k)
      return
    end if
    flush(u, iostat=stat, iomsg=msg)
    close(u, iostat=stat, iomsg=msg)
    if (stat /= 0) then
      errmsg = 'cannot close '//tmp//': '//trim(msg)
      return
    end if
    call sys_rename(tmp, fin, stat, errmsg)
  end subroutine checkpoint_write

  !> Read dir/checkpoint.bin into s, which setup_sim has built from the same input. Refuses
  !! (stat = 2) when the stored input differs from input_text or the sizes do not match.
  subroutine checkpoint_read(dir, input_text, s, ex, stat, errmsg)
    character(len=*), intent(in) :: dir          !! output folder
    character(len=*), intent(in) :: input_text   !! resolved input of the case now
    type(sim_t), intent(inout) :: s              !! simulation, set up from the input
    type(ckpt_extra_t), intent(out) :: ex        !! output positions
    integer, intent(out) :: stat                 !! 0; 2 mismatch; 3 I/O failure
    character(len=:), allocatable, intent(out) :: errmsg  !! what is wrong
    integer :: u, k, version, nlen, nsnap, ios
    character(len=12) :: m1, m2
    character(len=:), allocatable :: stored
    character(len=512) :: msg
    character(len=:), allocatable :: fin
    msg = ''
    m2 = ''
    fin = dir//'/checkpoint.bin'
    errmsg = ''
    open(newunit=u, file=fin, access='stream', form='unformatted', status='old', &
         action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      stat = 3
      errmsg = 'cannot open the checkpoint '//fin//': '//trim(msg)//'. A run writes '// &
               'checkpoints only with &run checkpoint_every > 0, or when it is interrupted'
      return
    end if
    stat = 3
    read(u, iostat=ios, iomsg=msg) m1, version, nlen
    if (ios == 0 .and. m1 == magic .and. version /= format_version) then
      errmsg = fin//' was written by another version of tubempm (checkpoint format '// &
               itoa(version)//'; this one reads format '//itoa(format_version)//'): '// &
               'continue it with the tubempm that wrote it, or start a new run'
      close(u, iostat=ios)
      return
    end if
    if (ios /= 0 .or. m1 /= magic .or. nlen < 0) then
      errmsg = fin//' is not a tubempm checkpoint of format version '// &
               itoa(format_version)//' (or is damaged)'
      close(u, iostat=ios)
      return
    end if
    allocate(character(len=nlen) :: stored)
    read(u, iostat=ios, iomsg=msg) stored
    if (ios /= 0) then
      errmsg = 'cannot read '//fin//': '//trim(msg)
      close(u, iostat=ios)
      return
    end if
    if (stored /= input_text) then
      stat = 2
      errmsg = dir//'/input.nml no longer matches the input the checkpoint was written '// &
        'with. Restore it (the checkpoint holds the original text), or start a new run'
      close(u, iostat=ios)
      return
    end if
    call grid_read_placement(s%g, u, ios, msg)
    if (ios == 0) call diag_read(s%diag, u, ios, msg)
    if (ios == 0) call state_read(s%state_t, u, ios, msg)
    if (ios == -1) then
      stat = 2
      errmsg = fin//': the particle, corner or wall counts differ from the input''s; '// &
               'the checkpoint belongs to another case'
      close(u, iostat=ios)
      return
    end if
    if (ios == 0) read(u, iostat=ios, iomsg=msg) ex%history_rows, ex%history_next, &
      ex%history_last, ex%snapshot_next, nsnap
    if (ios == 0 .and. nsnap >= 0) then
      allocate(ex%snap_times(nsnap), ex%snap_np(nsnap), ex%snap_nc(nsnap))
      read(u, iostat=ios, iomsg=msg) ex%snap_times, ex%snap_np, ex%snap_nc, ex%wall_seconds, &
        ex%contact_first, ex%contact_last, m2
    end if
    close(u, iostat=k)
    if (ios /= 0 .or. m2 /= magic) then
      errmsg = fin//' is truncated or damaged'
      return
    end if
    stat = 0
  end subroutine checkpoint_read
end module mpm_restart
