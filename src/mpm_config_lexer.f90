!> The input file as text: its lines, the groups (`&name ... /`) found in it, their tokens and
!! `name = value` assignments, and the messages collected while reading (each with its line).
! SPDX-License-Identifier: MIT
!
! Scanning the text once gives the line of every group and of every assignment, so that every
! message can say `file:line`, and lets the values be read and diagnosed precisely. The
! scanner (scan_source) is the one routine over 120 lines: it is a character state machine
! (outside a group, inside a group: comment, comma, '/', '=', '&', quote, word) whose branches
! share the scanning position; split up they would pass that state back and forth.
module mpm_config_lexer
  use, intrinsic :: iso_fortran_env, only: iostat_end, iostat_eor
  use mpm_errors, only: append_msg
  use mpm_config_text, only: lower, is_blank, name_end, word_end, string_end, compact, itoa, &
                             suggestion, join_list
  use mpm_config_table, only: n_groups, group_names, group_repeatable, group_id
  implicit none
  private
  public :: reader_t, occ_t, token_t, assign_t, tk_word, tk_string, tk_equals
  public :: load_lines, read_record, has_content, scan_source, check_groups, open_occ
  public :: add_err, add_warn, join_msgs, label, var_where, occurrence

  integer, parameter :: tk_word = 1, tk_string = 2, tk_equals = 3

  type :: text_line_t
    character(len=:), allocatable :: s
  end type text_line_t

  !> A token of a group's text: a word, a quoted text or '='.
  type :: token_t
    character(len=:), allocatable :: text
    integer :: line = 0
    integer :: kind = tk_word
    logical :: comma_comment = .false.   ! followed by ", ! comment" at the end of its line
    integer :: commas = 0                ! commas between the previous token and this one
  end type token_t

  !> `name = value ...` inside a group (or stray text when stray is true).
  type :: assign_t
    character(len=:), allocatable :: base    ! lower-case name without subscript
    character(len=:), allocatable :: sub     ! subscript text without parentheses, or ''
    character(len=:), allocatable :: value   ! the value tokens joined by ', '
    integer :: line = 0
    integer :: t1 = 1, t2 = 0                ! value tokens
    logical :: stray = .false.
  end type assign_t

  !> One occurrence of a group in the file.
  type :: occ_t
    character(len=:), allocatable :: group   ! lower case
    integer :: index = 0                     ! k-th occurrence of this group name
    integer :: line = 0, end_line = 0
    logical :: closed = .false.
    logical :: readable = .true.             ! false: structural error already reported
    logical :: read_ok = .false.             ! the namelist read succeeded
    logical :: ok = .true.                   ! read and validated without error
    integer :: n_tok = 0, n_asg = 0
    integer :: commas = 0                    ! commas since the last token
    type(token_t), allocatable :: tok(:)
    type(assign_t), allocatable :: asg(:)
  end type occ_t

  type :: msg_t
    integer :: line = 0
    character(len=:), allocatable :: text
  end type msg_t

  !> Everything known about the file being read, and the messages so far.
  type :: reader_t
    character(len=:), allocatable :: file
    integer :: n_lines = 0, n_occ = 0, n_err = 0, n_warn = 0
    type(text_line_t), allocatable :: lines(:)
    type(occ_t), allocatable :: occ(:)
    type(msg_t), allocatable :: err(:), warn(:)
  end type reader_t

contains

  !> All records of the file into rd%lines (any length).
  subroutine load_lines(rd, u, ios, iomsg)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: iomsg
    character(len=:), allocatable :: line
    type(text_line_t), allocatable :: tmp(:)
    do
      call read_record(u, line, ios, iomsg)
      if (ios /= 0) exit
      if (rd%n_lines == size(rd%lines)) then
        allocate(tmp(2*size(rd%lines)))
        tmp(1:rd%n_lines) = rd%lines(1:rd%n_lines)
        call move_alloc(tmp, rd%lines)
      end if
      rd%n_lines = rd%n_lines + 1
      rd%lines(rd%n_lines)%s = line
    end do
    if (ios == iostat_end) ios = 0
  end subroutine load_lines

  !> One record of any length; a last line without a newline counts as a record.
  subroutine read_record(u, line, ios, iomsg)
    integer, intent(in) :: u
    character(len=:), allocatable, intent(out) :: line
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: iomsg
    character(len=256) :: buf
    integer :: nread
    logical :: started
    line = ''
    started = .false.
    do
      nread = 0
      read(u, '(a)', advance='no', iostat=ios, iomsg=iomsg, size=nread) buf
      if (ios == 0) then
        line = line//buf
        started = .true.
      else if (ios == iostat_eor) then
        line = line//buf(1:nread)
        ios = 0
        return
      else if (ios == iostat_end) then
        if (started .or. nread > 0) then
          line = line//buf(1:nread)
          ios = 0
        end if
        return
      else
        return
      end if
    end do
  end subroutine read_record

  !> True when some line holds more than blanks and comments.
  pure logical function has_content(rd)
    type(reader_t), intent(in) :: rd
    integer :: il, ic
    character(len=1) :: c
    has_content = .false.
    do il = 1, rd%n_lines
      do ic = 1, len(rd%lines(il)%s)
        c = rd%lines(il)%s(ic:ic)
        if (c == '!') exit
        if (.not. is_blank(c)) then
          has_content = .true.
          return
        end if
      end do
    end do
  end function has_content

  ! ------------------------------------------------------------------------ scanning

  !> Find the groups (`&name ... /`) and tokenise their text; report text outside groups,
  !! groups not closed, and groups starting on the line where another one ends.
  subroutine scan_source(rd)
    type(reader_t), intent(inout) :: rd
    integer :: il, ic, n, j, cur, last_tok, io
    character(len=1) :: c
    character(len=:), allocatable :: line
    logical :: stray_done, comma_pending
    cur = 0
    do il = 1, rd%n_lines
      line = rd%lines(il)%s
      n = len(line)
      ic = 1
      stray_done = .false.
      comma_pending = .false.
      last_tok = 0
      do while (ic <= n)
        c = line(ic:ic)
        if (cur == 0) then                               ! outside any group
          if (c == '!') exit
          if (is_blank(c)) then
            ic = ic + 1
            cycle
          end if
          if (c == '&') then
            j = name_end(line, ic + 1)
            if (j > ic) then
              if (lower(line(ic+1:j)) /= 'end') then
                call open_occ(rd, lower(line(ic+1:j)), il)
                cur = rd%n_occ
                ic = j + 1
                cycle
              end if
            end if
          end if
          if (.not. stray_done) then
            call add_err(rd, il, 'text outside any group: '''// &
              trim(adjustl(line(ic:)))//''' (the namelist reader would ignore it; '// &
              'a misplaced ''/''?); allowed: comments starting with !, and groups &<name> ... /')
            stray_done = .true.
          end if
          exit
        end if
        select case (c)                                  ! inside group cur
        case ('!')
          if (comma_pending .and. last_tok > 0) rd%occ(cur)%tok(last_tok)%comma_comment = .true.
          exit
        case (',')
          comma_pending = .true.
          rd%occ(cur)%commas = rd%occ(cur)%commas + 1
          ic = ic + 1
        case ('/')
          rd%occ(cur)%closed = .true.
          rd%occ(cur)%end_line = il
          cur = 0
          ic = ic + 1
        case ('=')
          call push_token(rd%occ(cur), '=', il, tk_equals)
          last_tok = rd%occ(cur)%n_tok
          comma_pending = .false.
          ic = ic + 1
        case ('&')
          j = name_end(line, ic + 1)
          if (lower(line(ic+1:j)) == 'end') then
            rd%occ(cur)%closed = .true.
            rd%occ(cur)%end_line = il
            cur = 0
            ic = j + 1
          else
            call add_err(rd, rd%occ(cur)%line, label(rd, cur)//': not closed with ''/'' '// &
              'before line '//itoa(il)//'; allowed: end every group with a line holding /')
            rd%occ(cur)%readable = .false.
            rd%occ(cur)%end_line = il - 1
            cur = 0                                      ! the '&' opens the next group
          end if
        case ('''', '"')
          j = string_end(line, ic)
          if (j == 0) then
            call add_err(rd, il, label(rd, cur)//': text value '//line(ic:)// &
              ' is not closed on this line; allowed: text in matching quotes on one line')
            rd%occ(cur)%readable = .false.
            j = n
          end if
          call push_token(rd%occ(cur), line(ic:j), il, tk_string)
          last_tok = rd%occ(cur)%n_tok
          comma_pending = .false.
          ic = j + 1
        case default
          if (is_blank(c)) then
            ic = ic + 1
            cycle
          end if
          j = word_end(line, ic)
          call push_token(rd%occ(cur), line(ic:j), il, tk_word)
          last_tok = rd%occ(cur)%n_tok
          comma_pending = .false.
          ic = j + 1
        end select
      end do
    end do
    if (cur /= 0) then
      call add_err(rd, rd%occ(cur)%line, label(rd, cur)//': not closed with ''/'' (end of '// &
        'file reached); allowed: end every group with a line holding /')
      rd%occ(cur)%readable = .false.
      rd%occ(cur)%end_line = rd%n_lines
    end if
    do io = 1, rd%n_occ
      call build_assignments(rd%occ(io))
    end do
  end subroutine scan_source

  !> Start a new group occurrence at line il.
  subroutine open_occ(rd, name, il)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: name
    integer, intent(in) :: il
    type(occ_t), allocatable :: tmp(:)
    integer :: k, io
    if (rd%n_occ == size(rd%occ)) then
      allocate(tmp(2*size(rd%occ)))
      tmp(1:rd%n_occ) = rd%occ(1:rd%n_occ)
      call move_alloc(tmp, rd%occ)
    end if
    k = 1
    do io = 1, rd%n_occ
      if (rd%occ(io)%group == name) k = k + 1
    end do
    rd%n_occ = rd%n_occ + 1
    rd%occ(rd%n_occ)%group = name
    rd%occ(rd%n_occ)%index = k
    rd%occ(rd%n_occ)%line = il
    rd%occ(rd%n_occ)%end_line = il
    allocate(rd%occ(rd%n_occ)%tok(16), rd%occ(rd%n_occ)%asg(8))
    if (rd%n_occ > 1) then
      if (rd%occ(rd%n_occ - 1)%closed .and. rd%occ(rd%n_occ - 1)%end_line == il) then
        call add_err(rd, il, label(rd, rd%n_occ)//': starts on the line where '// &
          label(rd, rd%n_occ - 1)//' ends (the reader would skip it); allowed: each group '// &
          'starting on a line of its own')
        rd%occ(rd%n_occ)%readable = .false.
      end if
    end if
  end subroutine open_occ

  !> Append a token to an occurrence.
  subroutine push_token(o, text, line, kind)
    type(occ_t), intent(inout) :: o
    character(len=*), intent(in) :: text
    integer, intent(in) :: line, kind
    type(token_t), allocatable :: tmp(:)
    if (o%n_tok == size(o%tok)) then
      allocate(tmp(2*size(o%tok)))
      tmp(1:o%n_tok) = o%tok(1:o%n_tok)
      call move_alloc(tmp, o%tok)
    end if
    o%n_tok = o%n_tok + 1
    o%tok(o%n_tok)%text = text
    o%tok(o%n_tok)%line = line
    o%tok(o%n_tok)%kind = kind
    o%tok(o%n_tok)%commas = o%commas
    o%commas = 0
  end subroutine push_token

  !> Group the tokens of an occurrence into `name = values` (and stray text).
  subroutine build_assignments(o)
    type(occ_t), intent(inout) :: o
    integer :: it, ia, p, q, j
    character(len=:), allocatable :: w
    logical :: is_name
    ia = 0
    it = 1
    do while (it <= o%n_tok)
      is_name = .false.
      if (o%tok(it)%kind == tk_word .and. it < o%n_tok) is_name = o%tok(it+1)%kind == tk_equals
      if (is_name) then
        call new_asg(o, ia, it + 2, o%tok(it)%line, .false.)
        w = lower(o%tok(it)%text)
        p = index(w, '(')
        if (p > 0) then
          q = index(w, ')', back=.true.)
          if (q < p) q = len(w) + 1
          o%asg(ia)%base = trim(w(1:p-1))
          o%asg(ia)%sub = compact(w(p+1:q-1))
        else
          o%asg(ia)%base = w
          o%asg(ia)%sub = ''
        end if
        it = it + 2
        cycle
      end if
      if (ia == 0) then
        call new_asg(o, ia, it, o%tok(it)%line, .true.)
      else if (o%tok(it)%kind == tk_equals .and. .not. o%asg(ia)%stray) then
        call new_asg(o, ia, it, o%tok(it)%line, .true.)
      end if
      o%asg(ia)%t2 = it
      it = it + 1
    end do
    do ia = 1, o%n_asg
      o%asg(ia)%value = ''
      do j = o%asg(ia)%t1, o%asg(ia)%t2    ! the values as written, null values kept ('1, , 2')
        o%asg(ia)%value = o%asg(ia)%value//repeat(', ', max(merge(0, 1, j == o%asg(ia)%t1), &
          o%tok(j)%commas))//o%tok(j)%text
      end do
    end do
  end subroutine build_assignments

  !> Append an assignment whose values start at token t1.
  subroutine new_asg(o, ia, t1, line, stray)
    type(occ_t), intent(inout) :: o
    integer, intent(out) :: ia
    integer, intent(in) :: t1, line
    logical, intent(in) :: stray
    type(assign_t), allocatable :: tmp(:)
    if (o%n_asg == size(o%asg)) then
      allocate(tmp(2*size(o%asg)))
      tmp(1:o%n_asg) = o%asg(1:o%n_asg)
      call move_alloc(tmp, o%asg)
    end if
    o%n_asg = o%n_asg + 1
    ia = o%n_asg
    o%asg(ia)%t1 = t1
    o%asg(ia)%t2 = t1 - 1
    o%asg(ia)%line = line
    o%asg(ia)%stray = stray
    o%asg(ia)%base = ''
    o%asg(ia)%sub = ''
  end subroutine new_asg

  !> Unknown group names, repeated single groups, missing required groups.
  subroutine check_groups(rd, n_of, first_of)
    type(reader_t), intent(inout) :: rd
    integer, intent(out) :: n_of(n_groups)    !! occurrences of each known group
    integer, intent(out) :: first_of(n_groups) !! first occurrence (0 if none)
    integer :: io, ig
    character(len=:), allocatable :: lines_txt
    n_of = 0
    first_of = 0
    do io = 1, rd%n_occ
      ig = group_id(rd%occ(io)%group)
      if (ig == 0) then
        call add_err(rd, rd%occ(io)%line, '&'//rd%occ(io)%group//': unknown group'// &
          suggestion(rd%occ(io)%group, group_names)//'; allowed: '//join_list(group_names, '&'))
        rd%occ(io)%ok = .false.
        cycle
      end if
      n_of(ig) = n_of(ig) + 1
      if (first_of(ig) == 0) first_of(ig) = io
    end do
    do ig = 1, 3
      if (n_of(ig) > 1) then
        lines_txt = ''
        do io = 1, rd%n_occ
          if (rd%occ(io)%group /= trim(group_names(ig))) cycle
          if (len(lines_txt) > 0) lines_txt = lines_txt//', '
          lines_txt = lines_txt//itoa(rd%occ(io)%line)
          if (rd%occ(io)%index > 1) rd%occ(io)%ok = .false.
        end do
        do io = 1, rd%n_occ
          if (rd%occ(io)%group == trim(group_names(ig)) .and. rd%occ(io)%index == 2) &
            call add_err(rd, rd%occ(io)%line, '&'//trim(group_names(ig))//': group given '// &
              itoa(n_of(ig))//' times (lines '//lines_txt//'); allowed: once (merge them)')
        end do
      end if
    end do
    if (n_of(1) == 0) call add_err(rd, 0, '&run: group missing (required); add &run with at '// &
      'least t_end = <simulated time [s]>')
    if (n_of(3) == 0) call add_err(rd, 0, '&grid: group missing (required); add &grid with at '// &
      'least h = <cell size [m]>')
    if (n_of(4) == 0) call add_err(rd, 0, '&material: group missing (at least one required); '// &
      'add &material with name, E, nu, rho (and sigma_y for model = ''j2'')')
    if (n_of(5) == 0) call add_err(rd, 0, '&body: group missing (at least one required); add '// &
      '&body with r_inner and r_outer (a ring)')
  end subroutine check_groups



  !> Record an error at a line (0: none) of the file.
  subroutine add_err(rd, line, text)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: line
    character(len=*), intent(in) :: text
    call push_msg(rd%err, rd%n_err, line, file_line(rd, line)//text)
  end subroutine add_err

  !> Record a warning at a line (0: none) of the file.
  subroutine add_warn(rd, line, text)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: line
    character(len=*), intent(in) :: text
    call push_msg(rd%warn, rd%n_warn, line, file_line(rd, line)//text)
  end subroutine add_warn

  pure function file_line(rd, line) result(s)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: line
    character(len=:), allocatable :: s
    if (line > 0) then
      s = rd%file//':'//itoa(line)//': '
    else
      s = rd%file//': '
    end if
  end function file_line

  subroutine push_msg(list, n, line, text)
    type(msg_t), allocatable, intent(inout) :: list(:)
    integer, intent(inout) :: n
    integer, intent(in) :: line
    character(len=*), intent(in) :: text
    type(msg_t), allocatable :: tmp(:)
    if (n == size(list)) then
      allocate(tmp(2*size(list)))
      tmp(1:n) = list(1:n)
      call move_alloc(tmp, list)
    end if
    n = n + 1
    list(n)%line = line
    list(n)%text = text
  end subroutine push_msg

  !> Line and value text of variable var in occurrence io, as the last assignment to it wrote
  !> them (shown: var, or var(subscript) with the subscript's own value text).
  subroutine var_where(rd, io, var, value, ln, v, shown)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var, value
    integer, intent(out) :: ln
    character(len=:), allocatable, intent(out) :: v, shown
    integer :: ia, k
    ln = rd%occ(io)%line
    v = value
    shown = var
    ia = 0
    do k = rd%occ(io)%n_asg, 1, -1
      if (rd%occ(io)%asg(k)%stray) cycle
      if (rd%occ(io)%asg(k)%base == lower(var)) then
        ia = k
        exit
      end if
    end do
    if (ia == 0) return
    ln = rd%occ(io)%asg(ia)%line
    if (len(rd%occ(io)%asg(ia)%value) > 0) v = rd%occ(io)%asg(ia)%value
    if (len(rd%occ(io)%asg(ia)%sub) > 0) shown = var//'('//rd%occ(io)%asg(ia)%sub//')'
  end subroutine var_where

  !> Messages sorted by line (stable; messages without a line last), one per line.
  function join_msgs(list, n) result(s)
    type(msg_t), intent(in) :: list(:)
    integer, intent(in) :: n
    character(len=:), allocatable :: s
    integer :: idx(n), key(n), i, j, t
    do i = 1, n
      idx(i) = i
      key(i) = list(i)%line
      if (key(i) <= 0) key(i) = huge(1)
    end do
    do i = 2, n
      t = idx(i)
      j = i - 1
      do while (j >= 1)
        if (key(idx(j)) <= key(t)) exit
        idx(j+1) = idx(j)
        j = j - 1
      end do
      idx(j+1) = t
    end do
    s = ''
    do i = 1, n
      call append_msg(s, list(idx(i))%text)
    end do
  end function join_msgs

  !> '&group' or '&group #k' for repeatable groups.
  pure function label(rd, io) result(s)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    character(len=:), allocatable :: s
    integer :: ig
    s = '&'//rd%occ(io)%group
    ig = group_id(rd%occ(io)%group)
    if (ig > 0) then
      if (group_repeatable(ig)) s = s//' #'//itoa(rd%occ(io)%index)
    end if
  end function label

  !> The occurrence of the k-th group `group` (0 when there is none).
  pure integer function occurrence(rd, group, k) result(io)
    type(reader_t), intent(in) :: rd       !! the input's occurrences
    character(len=*), intent(in) :: group  !! group name, lower case
    integer, intent(in) :: k               !! k-th occurrence of that group
    integer :: i
    io = 0
    do i = 1, rd%n_occ
      if (rd%occ(i)%group == group .and. rd%occ(i)%index == k) then
        io = i
        return
      end if
    end do
  end function occurrence
end module mpm_config_lexer
