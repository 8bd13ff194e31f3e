!> The pre-scan of an input file: where each group starts, which variables it assigns, on which
!! line, with which value text; and the messages collected while reading (each with its line).
! SPDX-License-Identifier: MIT
!
! The scan strips comments, finds `&name ... /` (or `&end`), and splits each group's text at
! the `name =` of its assignments, so that every message can say file:line, group, variable
! and value, and an unknown name gets a suggestion. The values themselves are left to the
! compiler's namelist read (mpm_config_record); the scan only splits them into tokens for the
! messages (what was given, how many values, which token is wrong).
module mpm_config_scan
  use, intrinsic :: iso_fortran_env, only: iostat_end, iostat_eor
  use mpm_errors, only: append_msg
  use mpm_config_text, only: lower, is_blank, name_end, string_end, itoa, suggestion, join_list
  use mpm_config_table, only: group_names, group_repeatable, group_id, spec_index, var_names, &
                              specs, enum_names
  use mpm_config_record, only: rec_t, field_t, record_fields, field_index
  implicit none
  private
  public :: reader_t, occ_t, asg_t, load_lines, scan_source, check_groups, add_err, add_warn, &
            join_msgs, label, occurrence, err_var, err_missing, warn_group, given, &
            last_asg, value_tokens, allowed_text, tok_len

  integer, parameter :: tok_len = 2048      !! longest value token (a quoted path: 512)

  type :: line_t
    character(len=:), allocatable :: s
  end type line_t

  !> `name = value` in a group.
  type :: asg_t
    character(len=:), allocatable :: name    !! as written, without subscript
    character(len=:), allocatable :: sub     !! the subscript without parentheses, or ''
    character(len=:), allocatable :: value   !! the value text, tokens joined by ', '
    integer :: line = 0
    integer :: v0 = 1, v1 = 0                !! the value's characters in the group's body
  end type asg_t

  !> One occurrence of a group in the file.
  type :: occ_t
    character(len=:), allocatable :: group   !! lower case
    integer :: index = 0                     !! k-th occurrence of this group name
    integer :: line = 0
    logical :: readable = .true.             !! false: a structural error is reported
    logical :: read_ok = .false.             !! its assignments were read without error
    logical :: ok = .true.                   !! read and validated without error
    integer :: n_asg = 0
    type(asg_t), allocatable :: asg(:)
    character(len=:), allocatable :: body    !! the group's text without comments
    integer, allocatable :: at(:)            !! line of each character of body (0: in quotes)
  end type occ_t

  type :: msg_t
    integer :: line = 0
    character(len=:), allocatable :: text
  end type msg_t

  !> Everything known about the input being read, and the messages so far.
  type :: reader_t
    character(len=:), allocatable :: file
    logical :: numbered = .true.             !! messages give line numbers (a file)
    integer :: n_occ = 0, n_err = 0
    type(line_t), allocatable :: lines(:)
    type(occ_t), allocatable :: occ(:)
    type(msg_t), allocatable :: err(:), warn(:)
  end type reader_t

contains

  !> All records of a unit into rd%lines (any length; a last line without newline counts).
  subroutine load_lines(rd, u, ios, iomsg)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: iomsg
    character(len=256) :: buf
    character(len=:), allocatable :: line
    integer :: nread
    allocate(rd%lines(0))
    line = ''
    do
      read(u, '(a)', advance='no', iostat=ios, iomsg=iomsg, size=nread) buf
      if (ios /= 0 .and. ios /= iostat_eor .and. ios /= iostat_end) return
      line = line//buf(1:nread)
      if (ios == 0) cycle
      if (ios == iostat_end .and. len(line) == 0) exit
      rd%lines = [rd%lines, line_t(line)]
      line = ''
      if (ios == iostat_end) exit
    end do
    ios = 0
  end subroutine load_lines

  !> Find the groups and their assignments; report text outside groups, groups not closed and
  !! text values not closed on their line.
  subroutine scan_source(rd)
    type(reader_t), intent(inout) :: rd
    integer :: il, ic, j, cur
    character(len=:), allocatable :: s, w
    allocate(rd%occ(0), rd%err(0), rd%warn(0))
    cur = 0
    do il = 1, size(rd%lines)
      s = rd%lines(il)%s
      ic = 1
      do while (ic <= len(s))
        j = name_end(s, ic + 1)
        w = ''                                               ! the name after '&'
        if (j > ic) w = lower(s(ic+1:j))
        if (cur == 0) then                                   ! outside any group
          if (s(ic:ic) == '!') exit
          if (s(ic:ic) == '&' .and. len(w) > 0 .and. w /= 'end') then
            rd%occ = [rd%occ, occ_t(group=w, line=il, body='')]
            cur = size(rd%occ)
            rd%occ(cur)%index = n_named(rd, w, cur)
            allocate(rd%occ(cur)%at(0))
            ic = j + 1
          else if (.not. is_blank(s(ic:ic))) then
            call add_err(rd, il, 'text outside any group: '''//trim(adjustl(s(ic:)))// &
              ''' (the namelist reader would ignore it; a misplaced ''/''?); allowed: '// &
              'comments starting with !, and groups &<name> ... /')
            exit
          else
            ic = ic + 1
          end if
        else if (s(ic:ic) == '!') then
          exit
        else if (s(ic:ic) == '/' .or. (s(ic:ic) == '&' .and. w == 'end')) then
          call split_assignments(rd, cur)
          cur = 0
          ic = merge(ic + 1, j + 1, s(ic:ic) == '/')
        else if (s(ic:ic) == '&') then
          call add_err(rd, rd%occ(cur)%line, label(rd, cur)//': not closed with ''/'' '// &
            'before line '//itoa(il)//'; allowed: end every group with a line holding /')
          rd%occ(cur)%readable = .false.
          cur = 0                                            ! the '&' opens the next group
        else if (s(ic:ic) == '''' .or. s(ic:ic) == '"') then
          j = string_end(s, ic)
          if (j == 0) then
            call add_err(rd, il, label(rd, cur)//': text value '//s(ic:)//' is not closed '// &
              'on this line; allowed: text in matching quotes on one line')
            rd%occ(cur)%readable = .false.
            j = len(s)
          end if
          call push(rd%occ(cur), s(ic:j), 0)
          ic = j + 1
        else
          call push(rd%occ(cur), s(ic:ic), il)
          ic = ic + 1
        end if
      end do
      if (cur > 0) call push(rd%occ(cur), ' ', il)          ! a line end separates values
    end do
    if (cur > 0) then
      call add_err(rd, rd%occ(cur)%line, label(rd, cur)//': not closed with ''/'' (end of '// &
        'file reached); allowed: end every group with a line holding /')
      rd%occ(cur)%readable = .false.
    end if
  end subroutine scan_source

  !> Append text to a group's body; `line` 0 marks text in quotes (its line is the next one's).
  !! Tabs and carriage returns outside quotes become blanks.
  subroutine push(o, text, line)
    type(occ_t), intent(inout) :: o
    character(len=*), intent(in) :: text
    integer, intent(in) :: line
    if (line > 0 .and. is_blank(text(1:1))) then
      o%body = o%body//' '
    else
      o%body = o%body//text
    end if
    o%at = [o%at, spread(line, 1, len(text))]
  end subroutine push

  !> The assignments of a closed group: each '=' outside quotes ends a name (with an optional
  !! subscript) that starts an assignment; its value runs to the next one's name.
  subroutine split_assignments(rd, io)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    integer :: i, j, q, n, k
    integer, allocatable :: start(:), eq(:)
    character(len=:), allocatable :: b
    b = rd%occ(io)%body
    allocate(start(0), eq(0))
    do i = 1, len(b)
      if (b(i:i) /= '=' .or. rd%occ(io)%at(i) == 0) cycle
      j = len_trim(b(:i-1))
      if (j > 0) then
        if (b(j:j) == ')') j = len_trim(b(:index(b(:j), '(', back=.true.) - 1))
      end if
      q = j
      do while (q > 0)
        if (name_end(b(q:q), 1) /= 1) exit     ! b(q) is not a letter, digit or '_'
        q = q - 1
      end do
      if (q == j) cycle                         ! '=' with no name before it: part of a value
      start = [start, q + 1]
      eq = [eq, i]
    end do
    n = size(start)
    start = [start, len(b) + 1]
    if (verify(b(:start(1)-1), ' ,') > 0) then          ! (a comma may follow the name)
      call add_err(rd, line_at(rd%occ(io), 1), label(rd, io)//': unexpected text '''// &
        trim(adjustl(b(:start(1)-1)))//''' (expected <name> = <value>); allowed: '// &
        join_list(var_names(rd%occ(io)%group), ''))
      rd%occ(io)%readable = .false.
    end if
    allocate(rd%occ(io)%asg(n))
    rd%occ(io)%n_asg = n
    do k = 1, n
      associate (a => rd%occ(io)%asg(k))
        j = start(k + 1)
        a%name = trim(b(start(k):eq(k) - 1))
        a%sub = ''
        if (index(a%name, '(') > 0) then
          a%sub = a%name(index(a%name, '(') + 1:len(a%name) - 1)
          a%name = trim(a%name(:index(a%name, '(') - 1))
        end if
        a%value = join_list(value_tokens(b(eq(k) + 1:j - 1)), '')
        a%line = line_at(rd%occ(io), start(k))
        a%v0 = eq(k) + 1
        a%v1 = j - 1
      end associate
    end do
  end subroutine split_assignments

  !> The line of the character i of a group's body (the group's line when there is none).
  pure integer function line_at(o, i) result(il)
    type(occ_t), intent(in) :: o
    integer, intent(in) :: i
    integer :: k
    il = o%line
    do k = i, size(o%at)
      if (o%at(k) == 0) cycle
      il = o%at(k)
      return
    end do
  end function line_at

  !> The tokens of a value text: words and quoted texts, separated by commas and blanks; a
  !! comma with no token since the last one (or the '=') is a null value (an empty token).
  pure function value_tokens(v) result(t)
    character(len=*), intent(in) :: v
    character(len=tok_len), allocatable :: t(:)
    integer :: i, j
    logical :: fresh                         ! no token since the last comma
    allocate(t(0))
    fresh = .true.
    i = 1
    do while (i <= len(v))
      if (v(i:i) == ',') then
        if (fresh) t = [character(len=tok_len) :: t, '']
        fresh = .true.
        i = i + 1
      else if (is_blank(v(i:i))) then
        i = i + 1
      else
        j = i + scan(v(i:), ' ,') - 2
        if (j < i) j = len(v)
        if (v(i:i) == '''' .or. v(i:i) == '"') j = max(string_end(v, i), i)
        t = [character(len=tok_len) :: t, v(i:j)]
        fresh = .false.
        i = j + 1
      end if
    end do
  end function value_tokens

  !> Unknown groups, repeated single groups, missing required groups.
  subroutine check_groups(rd, n_of, first_of)
    type(reader_t), intent(inout) :: rd
    integer, intent(out) :: n_of(:)            !! occurrences of each known group
    integer, intent(out) :: first_of(:)        !! first occurrence (0 if none)
    integer :: io, ig, k
    character(len=:), allocatable :: lines_txt
    n_of = 0
    first_of = 0
    do io = 1, rd%n_occ
      ig = group_id(rd%occ(io)%group)
      if (ig == 0) then
        call add_err(rd, rd%occ(io)%line, '&'//rd%occ(io)%group//': unknown group'// &
          suggestion(rd%occ(io)%group, group_names)//'; allowed: '//join_list(group_names, '&'))
        rd%occ(io)%readable = .false.
        cycle
      end if
      n_of(ig) = n_of(ig) + 1
      if (first_of(ig) == 0) first_of(ig) = io
      if (group_repeatable(ig) .or. rd%occ(io)%index == 1) cycle
      rd%occ(io)%readable = .false.
      if (rd%occ(io)%index > 2) cycle
      lines_txt = ''
      do k = 1, rd%n_occ
        if (rd%occ(k)%group /= rd%occ(io)%group) cycle
        if (len(lines_txt) > 0) lines_txt = lines_txt//', '
        lines_txt = lines_txt//itoa(rd%occ(k)%line)
      end do
      call add_err(rd, rd%occ(io)%line, '&'//rd%occ(io)%group//': group given '// &
        itoa(n_named(rd, rd%occ(io)%group, size(rd%occ)))//' times (lines '//lines_txt// &
        '); allowed: once (merge them)')
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

  ! ------------------------------------------------------------------------ messages

  !> Record an error at a line (0: none) of the file.
  subroutine add_err(rd, line, text)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: line
    character(len=*), intent(in) :: text
    rd%err = [rd%err, msg_t(line, file_line(rd, line)//text)]
    rd%n_err = size(rd%err)
  end subroutine add_err

  !> Record a warning at a line (0: none) of the file.
  subroutine add_warn(rd, line, text)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: line
    character(len=*), intent(in) :: text
    rd%warn = [rd%warn, msg_t(line, file_line(rd, line)//text)]
  end subroutine add_warn

  pure function file_line(rd, line) result(s)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: line
    character(len=:), allocatable :: s
    s = rd%file//': '
    if (line > 0 .and. rd%numbered) s = rd%file//':'//itoa(line)//': '
  end function file_line

  !> Messages sorted by line (stable; messages without a line last), one per line.
  function join_msgs(list) result(s)
    type(msg_t), intent(in) :: list(:)
    character(len=:), allocatable :: s
    integer :: key(size(list)), i, j
    logical :: done(size(list))
    key = list%line
    where (key <= 0) key = huge(1)
    done = .false.
    s = ''
    do i = 1, size(list)
      j = minloc(key, mask=.not. done, dim=1)
      done(j) = .true.
      call append_msg(s, list(j)%text)
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
    do io = 1, rd%n_occ
      if (rd%occ(io)%group == group .and. rd%occ(io)%index == k) return
    end do
    io = 0
  end function occurrence

  !> How many of the first `upto` occurrences are of group `group`.
  pure integer function n_named(rd, group, upto) result(n)
    type(reader_t), intent(in) :: rd
    character(len=*), intent(in) :: group
    integer, intent(in) :: upto
    integer :: io
    n = 0
    do io = 1, upto
      if (rd%occ(io)%group == group) n = n + 1
    end do
  end function n_named

  !> The last assignment to var in occurrence io (0: none).
  pure integer function last_asg(rd, io, var) result(ia)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    do ia = rd%occ(io)%n_asg, 1, -1
      if (lower(rd%occ(io)%asg(ia)%name) == lower(var)) return
    end do
    ia = 0
  end function last_asg

  !> Whether occurrence io assigns var.
  pure logical function given(rd, io, var)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    given = last_asg(rd, io, var) > 0
  end function given

  !> What variable var of a group accepts (for a list: the names and the default).
  function allowed_text(group, var) result(s)
    character(len=*), intent(in) :: group, var
    character(len=:), allocatable :: s
    integer :: k
    type(rec_t) :: d
    type(field_t), allocatable :: f(:)
    k = spec_index(group, var)
    s = 'see docs/input.md'
    if (k == 0) return
    s = trim(specs(k)%allowed)
    if (size(enum_names(trim(specs(k)%name))) == 0) return
    f = record_fields(group_id(group), d)   ! the type's default
    s = f(field_index(f, trim(specs(k)%name)))%s
    s = join_list(enum_names(trim(specs(k)%name)), '''')//' (default '''//trim(s)//''')'
  end function allowed_text

  !> `file:line: &group #k: var = value: what; allowed: ...` for occurrence io; the line and
  !! the value are those of the variable's last assignment when the input has one (given by a
  !! subscript or with null values, the whole value `value` follows in brackets). warn: a
  !! warning instead, with the group's section of docs/input.md in place of allowed.
  subroutine err_var(rd, io, var, value, what, allowed, warn)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var, value, what
    character(len=*), intent(in), optional :: allowed
    logical, intent(in), optional :: warn
    integer :: ia, ln
    character(len=:), allocatable :: v, shown, allow
    ln = rd%occ(io)%line
    v = value
    shown = var
    ia = last_asg(rd, io, var)
    if (ia > 0) then
      ln = rd%occ(io)%asg(ia)%line
      if (len(rd%occ(io)%asg(ia)%value) > 0) v = rd%occ(io)%asg(ia)%value
      if (len(rd%occ(io)%asg(ia)%sub) > 0) shown = var//'('//rd%occ(io)%asg(ia)%sub//')'
      if (len(value) > 0 .and. (shown /= var .or. index(', '//v, ', ,') > 0)) &
        v = v//' (so '//var//' = '//value//')'
    else if (len(value) > 0) then
      v = value//' (not in the file: resolved from the other groups)'
    end if
    allow = allowed_text(rd%occ(io)%group, var)
    if (present(allowed)) allow = allowed
    if (len(v) > 0) shown = shown//' = '//v
    if (present(warn)) then
      if (warn) call add_warn(rd, ln, label(rd, io)//': '//shown//': '//what// &
        ' (docs/input.md#'//rd%occ(io)%group//')')
      if (warn) return
    end if
    call add_err(rd, ln, label(rd, io)//': '//shown//': '//what//'; allowed: '//allow)
    rd%occ(io)%ok = .false.
  end subroutine err_var

  !> A required variable is missing in occurrence io.
  subroutine err_missing(rd, io, var)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    call add_err(rd, rd%occ(io)%line, label(rd, io)//': '//var//': missing (required); '// &
      'allowed: '//allowed_text(rd%occ(io)%group, var))
    rd%occ(io)%ok = .false.
  end subroutine err_missing

  !> A warning about occurrence io as a whole, with the group's section of docs/input.md.
  subroutine warn_group(rd, io, what)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: what
    call add_warn(rd, rd%occ(io)%line, label(rd, io)//': '//what//' (docs/input.md#'// &
      rd%occ(io)%group//')')
  end subroutine warn_group
end module mpm_config_scan
