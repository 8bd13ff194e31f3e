!> Text helpers of the input reader: names, quotes, suggestions, and numbers written in the
!! shortest form that reads back exactly.
! SPDX-License-Identifier: MIT
module mpm_config_text
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  use mpm_kinds, only: wp
  use mpm_constants, only: name_len
  use mpm_config_types, only: unset_real
  use mpm_strings, only: itoa            ! re-exported for the reader's modules
  implicit none
  private
  public :: join_list, suggestion, lower, is_blank, name_end, string_end, itoa, quote, &
            unquote, fmt_real, fmt_short, fmt_list, finite

contains

  !> True when x is finite and not NaN (NaN tested first: no FP trap).
  elemental logical function finite(x)
    real(wp), intent(in) :: x
    finite = .false.
    if (ieee_is_nan(x)) return
    finite = ieee_is_finite(x)
  end function finite

  !> 'a, b, c' with each name after prefix ('&' for groups, a quote for values).
  pure function join_list(names, prefix) result(s)
    character(len=*), intent(in) :: names(:), prefix
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(names)
      if (k > 1) s = s//', '
      s = s//prefix//trim(names(k))
      if (prefix == '''') s = s//''''
    end do
  end function join_list

  !> ' (did you mean ''x''?)' for the closest name, or ''.
  pure function suggestion(word, names) result(s)
    character(len=*), intent(in) :: word, names(:)
    character(len=:), allocatable :: s
    integer :: k, d, best, kbest, lw, ln
    s = ''
    best = huge(1)
    kbest = 0
    do k = 1, size(names)
      d = edit_distance(lower(word), lower(trim(names(k))))
      if (d < best) then
        best = d
        kbest = k
      end if
    end do
    if (kbest == 0) return
    lw = len(word)
    ln = len_trim(names(kbest))
    if ((best <= 2 .and. best < min(lw, ln)) .or. &
        (min(lw, ln) >= 3 .and. index(lower(trim(names(kbest))), lower(word)) == 1) .or. &
        (min(lw, ln) >= 3 .and. index(lower(word), lower(trim(names(kbest)))) == 1)) &
      s = ' (did you mean '''//trim(names(kbest))//'''?)'
  end function suggestion

  !> Levenshtein distance.
  pure integer function edit_distance(a, b) result(d)
    character(len=*), intent(in) :: a, b
    integer :: row(0:len(b)), prev(0:len(b)), i, j
    do j = 0, len(b)
      prev(j) = j
    end do
    do i = 1, len(a)
      row(0) = i
      do j = 1, len(b)
        row(j) = min(prev(j) + 1, row(j-1) + 1, prev(j-1) + merge(0, 1, a(i:i) == b(j:j)))
      end do
      prev = row
    end do
    d = prev(len(b))
  end function edit_distance

  !> The text in lower case (ASCII letters).
  elemental function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: k, c
    t = s
    do k = 1, len(s)
      c = iachar(s(k:k))
      if (c >= iachar('A') .and. c <= iachar('Z')) t(k:k) = achar(c + 32)
    end do
  end function lower

  elemental logical function is_blank(c)
    character(len=1), intent(in) :: c
    is_blank = c == ' ' .or. c == achar(9) .or. c == achar(13) .or. c == achar(10)
  end function is_blank

  !> Last index of the name (letters, digits, '_') starting at i (i - 1 when there is none).
  pure integer function name_end(s, i) result(j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: i
    j = i - 1
    do while (j + 1 <= len(s))
      if (verify(s(j+1:j+1), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_') &
          /= 0) exit
      j = j + 1
    end do
  end function name_end

  !> Index of the quote closing the text that opens at i ('' and "" inside), 0 if none.
  pure integer function string_end(s, i) result(j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: i
    j = i + 1
    do while (j <= len(s))
      if (s(j:j) == s(i:i)) then
        if (j == len(s)) return
        if (s(j+1:j+1) /= s(i:i)) return
        j = j + 1
      end if
      j = j + 1
    end do
    j = 0
  end function string_end

  !> Text in single quotes, inner quotes doubled (namelist syntax).
  pure function quote(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: k
    t = ''''
    do k = 1, len(s)
      t = t//s(k:k)
      if (s(k:k) == '''') t = t//''''
    end do
    t = t//''''
  end function quote

  !> The text of a quoted value without its quotes, doubled quotes made single.
  pure function unquote(t) result(s)
    character(len=*), intent(in) :: t
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    k = 2
    do while (k <= len(t) - 1)
      s = s//t(k:k)
      if (t(k:k) == t(1:1)) k = k + 1
      k = k + 1
    end do
  end function unquote

  !> Shortest decimal text that reads back to exactly x (NaN, Infinity for non-finite).
  function fmt_real(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=48) :: buf
    character(len=16) :: fmt
    character(len=:), allocatable :: b, digits
    integer :: d, ios, p, e
    real(wp) :: y
    character(len=128) :: msg
    if (ieee_is_nan(x)) then
      s = 'NaN'
      return
    end if
    if (.not. ieee_is_finite(x)) then
      s = trim(merge('-Infinity', 'Infinity ', x < 0.0_wp))
      return
    end if
    if (x == 0.0_wp) then
      s = '0.0'
      return
    end if
    do d = 0, 17
      if (abs(x) > 1.0e307_wp .and. d < 16) cycle        ! rounding up could overflow on reading
      write(fmt, '(a,i0,a)', iostat=ios, iomsg=msg) '(es40.', d, 'e4)'
      write(buf, fmt, iostat=ios, iomsg=msg) x
      read(buf, *, iostat=ios, iomsg=msg) y
      if (ios == 0 .and. y == x) exit
    end do
    b = trim(adjustl(buf))
    if (x < 0.0_wp) b = b(2:)
    p = index(b, 'E')
    read(b(p+1:), *, iostat=ios, iomsg=msg) e
    digits = b(1:1)//b(3:p-1)                         ! d.ddd -> dddd
    do while (len(digits) > 1)
      if (digits(len(digits):len(digits)) /= '0') exit
      digits = digits(1:len(digits)-1)
    end do
    if (e >= 0 .and. e <= 4) then                      ! plain decimal
      if (len(digits) <= e + 1) then
        s = digits//repeat('0', e + 1 - len(digits))//'.0'
      else
        s = digits(1:e+1)//'.'//digits(e+2:)
      end if
    else if (e < 0 .and. e >= -3) then
      s = '0.'//repeat('0', -e - 1)//digits
    else if (len(digits) > 1) then
      s = digits(1:1)//'.'//digits(2:)//'e'//itoa(e)
    else
      s = digits//'.0e'//itoa(e)
    end if
    if (x < 0.0_wp) s = '-'//s
  end function fmt_real

  !> Six significant digits, for derived numbers in messages.
  function fmt_short(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    real(wp) :: y
    integer :: ios
    character(len=128) :: msg
    s = fmt_real(x)
    if (.not. finite(x)) return
    write(buf, '(es13.5e3)', iostat=ios, iomsg=msg) x
    read(buf, *, iostat=ios, iomsg=msg) y
    if (ios == 0) s = fmt_real(y)
  end function fmt_short

  !> Numbers 'a, b, c'; an entry not given (unset_real) shows as (none).
  function fmt_list(v) result(s)
    real(wp), intent(in) :: v(:)
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(v)
      if (k > 1) s = s//', '
      if (v(k) == unset_real .and. finite(v(k))) then
        s = s//'(none)'
      else
        s = s//fmt_real(v(k))
      end if
    end do
  end function fmt_list
end module mpm_config_text
