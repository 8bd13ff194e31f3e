!> Numbers to text for messages.
! SPDX-License-Identifier: MIT
module mpm_strings
  use mpm_kinds, only: wp, i8
  implicit none
  private
  public :: itoa, rtoa

  !> Integer (default or 64-bit) to text without blanks.
  interface itoa
    module procedure itoa4, itoa8
  end interface itoa

contains

  !> Default integer to text.
  pure function itoa4(i) result(str)
    integer, intent(in) :: i               !! value
    character(len=:), allocatable :: str
    character(len=24) :: buf
    write(buf, '(i0)') i
    str = trim(buf)
  end function itoa4

  !> 64-bit integer to text.
  pure function itoa8(i) result(str)
    integer(i8), intent(in) :: i           !! value
    character(len=:), allocatable :: str
    character(len=24) :: buf
    write(buf, '(i0)') i
    str = trim(buf)
  end function itoa8

  !> Real to text with 5 significant digits.
  pure function rtoa(x) result(str)
    real(wp), intent(in) :: x              !! value
    character(len=:), allocatable :: str
    character(len=32) :: buf
    write(buf, '(es12.4e3)') x
    str = trim(adjustl(buf))
  end function rtoa
end module mpm_strings
