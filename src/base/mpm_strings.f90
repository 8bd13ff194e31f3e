!> Numbers to text for messages.
! SPDX-License-Identifier: MIT
module mpm_strings
  use mpm_kinds, only: wp, i8
  implicit none
  private
  public :: itoa, rtoa, sci, hms, plural

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

  !> Real to text in scientific notation with d digits after the point and an exponent of two
  !! digits, or three where it needs them ('2.581E-02', '1.000E-300'; a plain es edit descriptor
  !! drops the E of a three-digit exponent: '1.000-300').
  pure function sci(x, d) result(str)
    real(wp), intent(in) :: x              !! value
    integer, intent(in) :: d               !! digits after the decimal point (0-15)
    character(len=:), allocatable :: str
    character(len=40) :: buf
    character(len=16) :: fmt
    integer :: ie
    write(fmt, '(a,i0,a,i0,a)') '(es', d + 12, '.', max(0, min(d, 15)), 'e3)'
    write(buf, fmt) x
    str = trim(adjustl(buf))
    ie = index(str, 'E')
    if (ie > 0 .and. len(str) == ie + 4) then
      if (str(ie + 2:ie + 2) == '0') str = str(:ie + 1)//str(ie + 3:)
    end if
  end function sci

  !> A duration as h:mm:ss (rounded to the second; hours not limited) [s -> text].
  pure function hms(seconds) result(str)
    real(wp), intent(in) :: seconds        !! duration [s]
    character(len=:), allocatable :: str
    character(len=32) :: buf
    integer(i8) :: total
    total = nint(max(0.0_wp, min(seconds, 1.0e15_wp)), i8)
    write(buf, '(i0,a,i2.2,a,i2.2)') total/3600_i8, ':', mod(total/60_i8, 60_i8), ':', &
      mod(total, 60_i8)
    str = trim(buf)
  end function hms

  !> 'n word' or 'n words' (the plural by an added s).
  pure function plural(n, word) result(str)
    integer, intent(in) :: n               !! count
    character(len=*), intent(in) :: word   !! singular
    character(len=:), allocatable :: str
    str = itoa(n)//' '//word
    if (n /= 1) str = str//'s'
  end function plural
end module mpm_strings
