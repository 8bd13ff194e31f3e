!> Error reporting. Library code returns (stat, errmsg); only the driver calls fatal().
! SPDX-License-Identifier: MIT
module mpm_errors
  use, intrinsic :: iso_fortran_env, only: error_unit
  use mpm_sys, only: sys_exit
  implicit none
  private
  public :: fatal, warn, append_msg, halt

contains

  !> Print one or more `ERROR [where]: ...` lines and exit with `code` (an EXIT_* code of
  !! docs/output.md, or 128 + signal after SIGINT/SIGTERM), printing nothing else.
  !! A message holding several lines (separated by new_line) gets one ERROR prefix per line.
  subroutine fatal(where, msg, code)
    character(len=*), intent(in) :: where  !! the routine or stage that failed
    character(len=*), intent(in) :: msg    !! what failed and how to fix it
    integer, intent(in) :: code            !! EXIT_* code
    integer :: i0, i1
    i0 = 1
    do
      i1 = index(msg(i0:), new_line('a'))
      if (i1 == 0) then
        if (len_trim(msg(i0:)) > 0) write(error_unit, '(4a)') 'ERROR [', where, ']: ', trim(msg(i0:))
        exit
      end if
      if (i1 > 1) write(error_unit, '(4a)') 'ERROR [', where, ']: ', msg(i0:i0+i1-2)
      i0 = i0 + i1
      if (i0 > len(msg)) exit
    end do
    flush(error_unit)
    ! the project's own lines only: ERROR STOP would add its own line and a backtrace
    call sys_exit(code)
  end subroutine fatal

  !> A stop that is not an error (an interrupt: SIGINT, SIGTERM): msg on standard error as it
  !! is, then exit with `code` (128 + the signal, as shells report it).
  subroutine halt(msg, code)
    character(len=*), intent(in) :: msg    !! what stopped the run and how to go on
    integer, intent(in) :: code            !! exit status
    write(error_unit, '(a)') trim(msg)
    flush(error_unit)
    call sys_exit(code)
  end subroutine halt

  !> Print `WARNING [where]: msg` on standard error (runs go on).
  subroutine warn(where, msg)
    character(len=*), intent(in) :: where  !! the routine or stage
    character(len=*), intent(in) :: msg    !! the warning
    write(error_unit, '(4a)') 'WARNING [', where, ']: ', trim(msg)
    flush(error_unit)
  end subroutine warn

  !> Append a line to an accumulating multi-line message (for reporting all violations at once).
  pure subroutine append_msg(errmsg, line)
    character(len=:), allocatable, intent(inout) :: errmsg  !! message so far (may be unallocated)
    character(len=*), intent(in) :: line                     !! the new line
    if (.not. allocated(errmsg)) then
      errmsg = trim(line)
    else if (len(errmsg) == 0) then
      errmsg = trim(line)
    else
      errmsg = errmsg//new_line('a')//trim(line)
    end if
  end subroutine append_msg
end module mpm_errors
