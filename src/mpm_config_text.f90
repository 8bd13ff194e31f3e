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
  public :: enum_text, join_list, suggestion, lower, is_blank, name_end, word_end, &
            string_end, compact, itoa, quote, unquote, file_stem, fmt_real, fmt_short, &
            fmt_vec, fmt_list, fmt_logical, finite

contains

  !> True when x is finite and not NaN (NaN tested first: no FP trap).
  elemental logical function finite(x)
    real(wp), intent(in) :: x
    finite = .false.
    if (ieee_is_nan(x)) return
    finite = ieee_is_finite(x)
  end function finite


  pure function enum_text(names, default) result(s)
    character(len=*), intent(in) :: names(:), default
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(names)
      if (k > 1) s = s//', '
      s = s//quote(trim(names(k)))
    end do
    s = s//' (default '//quote(default)//')'
  end function enum_text

  pure function join_list(names, prefix) result(s)
    character(len=*), intent(in) :: names(:), prefix
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(names)
      if (k > 1) s = s//', '
      s = s//prefix//trim(names(k))
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

  ! ------------------------------------------------------------------------ text utilities

  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: k, c
    t = s
    do k = 1, len(s)
      c = iachar(s(k:k))
      if (c >= iachar('A') .and. c <= iachar('Z')) t(k:k) = achar(c + 32)
    end do
  end function lower

  pure logical function is_blank(c)
    character(len=1), intent(in) :: c
    is_blank = c == ' ' .or. c == achar(9) .or. c == achar(13) .or. c == achar(10)
  end function is_blank

  pure logical function is_name_char(c)
    character(len=1), intent(in) :: c
    is_name_char = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z') .or. &
                   (c >= '0' .and. c <= '9') .or. c == '_'
  end function is_name_char

  !> Last index of the name starting at i (i - 1 when there is none).
  pure integer function name_end(s, i) result(j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: i
    j = i - 1
    do while (j + 1 <= len(s))
      if (.not. is_name_char(s(j+1:j+1))) exit
      j = j + 1
    end do
  end function name_end

  !> Last index of the word starting at i; `name(...)` counts as one word.
  pure integer function word_end(s, i) result(j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: i
    integer :: p
    character(len=1) :: c
    j = i
    do while (j + 1 <= len(s))
      c = s(j+1:j+1)
      if (is_blank(c) .or. index(',=/!''"', c) > 0) exit
      if (c == '(') then
        p = index(s(j+1:), ')')
        if (p == 0) then
          j = len(s)
          exit
        end if
        j = j + p
        cycle
      end if
      j = j + 1
    end do
  end function word_end

  !> Index of the quote closing the text that opens at i ('' and "" inside), 0 if none.
  pure integer function string_end(s, i) result(j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: i
    character(len=1) :: q
    q = s(i:i)
    j = i + 1
    do while (j <= len(s))
      if (s(j:j) == q) then
        if (j + 1 <= len(s)) then
          if (s(j+1:j+1) == q) then
            j = j + 2
            cycle
          end if
        end if
        return
      end if
      j = j + 1
    end do
    j = 0
  end function string_end

  !> s without blanks.
  pure function compact(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: k
    t = ''
    do k = 1, len(s)
      if (.not. is_blank(s(k:k))) t = t//s(k:k)
    end do
  end function compact

  !> Text in single quotes, inner quotes doubled (namelist syntax).
  pure function quote(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: k
    t = ''''
    do k = 1, len(s)
      if (s(k:k) == '''') then
        t = t//''''''
      else
        t = t//s(k:k)
      end if
    end do
    t = t//''''
  end function quote

  !> Name of the file without folder and extension.
  pure function file_stem(path) result(stem)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: stem
    integer :: i, j
    i = index(path, '/', back=.true.)
    stem = trim(path(i+1:))
    j = index(stem, '.', back=.true.)
    if (j > 1) stem = stem(1:j-1)
    if (len(stem) == 0) stem = 'case'
    if (len(stem) > name_len) stem = stem(1:name_len)
  end function file_stem

  !> Shortest decimal text that reads back to exactly x (NaN, Infinity for non-finite).
  function fmt_real(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=48) :: buf
    character(len=16) :: fmt
    character(len=:), allocatable :: b, digits
    integer :: d, ios, p, e
    real(wp) :: y
    logical :: neg
    character(len=128) :: msg
    if (ieee_is_nan(x)) then
      s = 'NaN'
      return
    end if
    if (.not. ieee_is_finite(x)) then
      s = 'Infinity'
      if (x < 0.0_wp) s = '-Infinity'
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
    neg = b(1:1) == '-'
    if (neg) b = b(2:)
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
    else
      if (len(digits) > 1) then
        s = digits(1:1)//'.'//digits(2:)//'e'//itoa(e)
      else
        s = digits//'.0e'//itoa(e)
      end if
    end if
    if (neg) s = '-'//s
  end function fmt_real

  !> Six significant digits, for derived numbers in messages.
  function fmt_short(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    real(wp) :: y
    integer :: ios
    character(len=128) :: msg
    if (.not. finite(x)) then
      s = fmt_real(x)
      return
    end if
    write(buf, '(es13.5e3)', iostat=ios, iomsg=msg) x
    read(buf, *, iostat=ios, iomsg=msg) y
    s = trim(adjustl(buf))
    if (ios == 0) s = fmt_real(y)
  end function fmt_short

  !> Two numbers; a component not given shows as (none).
  function fmt_vec(v) result(s)
    real(wp), intent(in) :: v(2)
    character(len=:), allocatable :: s
    s = fmt_given(v(1))//', '//fmt_given(v(2))
  end function fmt_vec

  function fmt_given(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    s = fmt_real(x)
    if (x == unset_real) s = '(none)'   ! (false for NaN and the infinities)
  end function fmt_given

  function fmt_list(v) result(s)
    real(wp), intent(in) :: v(:)
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(v)
      if (k > 1) s = s//', '
      s = s//fmt_given(v(k))
    end do
  end function fmt_list

  pure function fmt_logical(l) result(s)
    logical, intent(in) :: l
    character(len=:), allocatable :: s
    s = trim(merge('.true. ', '.false.', l))
  end function fmt_logical

  !> The text of a quoted value without its quotes, doubled quotes made single.
  pure function unquote(t) result(s)
    character(len=*), intent(in) :: t
    character(len=:), allocatable :: s
    integer :: k
    character(len=1) :: q
    s = ''
    if (len(t) < 2) return
    q = t(1:1)
    k = 2
    do while (k <= len(t) - 1)
      s = s//t(k:k)
      if (t(k:k) == q) k = k + 1
      k = k + 1
    end do
  end function unquote
end module mpm_config_text
