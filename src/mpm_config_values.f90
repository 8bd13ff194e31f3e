!> The values of one group occurrence, read from its assignments as the table describes them,
!! and the checks that report a bad value with its line, group, variable and what is allowed.
! SPDX-License-Identifier: MIT
!
! Every assignment is diagnosed first (name known to the group, subscript, value types and
! count, quotes); only a group without such errors is read. The values start from the table's
! r0/i0/c0, so that a group can tell a value that was not given from one that was.
module mpm_config_values
  use mpm_kinds, only: wp
  use mpm_constants, only: max_table, name_len
  use mpm_config_types, only: unset_real, iunset
  use mpm_config_text, only: lower, itoa, quote, unquote, suggestion, fmt_real, fmt_vec, &
                             fmt_list, finite, join_list
  use mpm_config_table, only: specs, n_specs, spec_index, var_list, var_names, allowed_text, &
                              enum_names, group_specs, field_t
  use mpm_config_lexer, only: reader_t, tk_string, add_err, add_warn, label, var_where
  implicit none
  private
  public :: values_t, read_group, long_len, store_rows, fields_values
  public :: vreal, vvec, vtab, vint, vtext
  public :: chk_r, chk_v, table_count, for_shape
  public :: err_var, err_missing, warn_var, warn_group

  integer, parameter :: long_len = 1024         !! text buffers (longer than allowed)

  !> The values of one occurrence: column k holds row k of the table.
  type :: values_t
    character(len=8) :: group = ''
    real(wp) :: r(2*max_table, n_specs) = 0.0_wp  !! (the longest row: a tube's vertices)
    integer :: i(n_specs) = 0
    logical :: l(n_specs) = .false.
    character(len=long_len) :: c(n_specs) = ''
  end type values_t

contains

  !> Diagnose and read occurrence io into v; ok is false (and the group not usable) when it
  !! had structural errors or any assignment was wrong.
  subroutine read_group(rd, io, v, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io                !! occurrence
    type(values_t), intent(out) :: v         !! its values (table start values where not given)
    logical, intent(out) :: ok
    integer :: n0, k
    integer, allocatable :: idx(:)
    ok = .false.
    rd%occ(io)%ok = .false.
    if (.not. rd%occ(io)%readable) return
    v%group = rd%occ(io)%group
    idx = group_specs(v%group)
    do k = 1, size(idx)
      associate (s => specs(idx(k)))
        v%r(:, idx(k)) = s%r0
        v%i(idx(k)) = s%i0
        v%c(idx(k)) = s%c0
        v%l(idx(k)) = s%l0
        if (s%c_blank) v%c(idx(k)) = ''
      end associate
    end do
    n0 = rd%n_err
    call diagnose(rd, io, .false.)
    if (rd%n_err > n0) then             ! the group cannot be read: report it strictly
      rd%n_err = n0
      call diagnose(rd, io, .true.)
      return
    end if
    call parse_values(rd, io, v)
    call warn_repeated(rd, io)
    rd%occ(io)%read_ok = .true.
    ok = .true.
  end subroutine read_group

  !> Store the values of every assignment of a diagnosed occurrence (later ones win; `r*x` is
  !! r copies of x, `r*` skips r values).
  subroutine parse_values(rd, io, v)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    type(values_t), intent(inout) :: v
    integer :: ia, it, k, pos, p, r, j, ios
    character(len=:), allocatable :: t, rest, sub
    character(len=256) :: msg
    associate (o => rd%occ(io))
      do ia = 1, o%n_asg
        if (o%asg(ia)%stray) cycle
        k = spec_index(v%group, o%asg(ia)%base)
        pos = 1
        sub = o%asg(ia)%sub
        if (len(sub) > 0) then
          p = index(sub, ':')
          if (p == 0) p = len(sub) + 1
          read(sub(1:p-1), *, iostat=ios, iomsg=msg) pos
        end if
        do it = o%asg(ia)%t1, o%asg(ia)%t2
          t = o%tok(it)%text
          pos = pos + nulls(o%tok(it)%commas, it == o%asg(ia)%t1)
          if (o%tok(it)%kind == tk_string .or. index('ce', specs(k)%kind) > 0) then
            v%c(k) = t
            if (o%tok(it)%kind == tk_string) v%c(k) = unquote(t)
            pos = pos + 1
            cycle
          end if
          call split_repeat(t, r, rest)
          do j = 1, r
            if (len(rest) > 0) then
              select case (specs(k)%kind)
              case ('r')
                read(rest, *, iostat=ios, iomsg=msg) v%r(pos, k)
              case ('i')
                read(rest, *, iostat=ios, iomsg=msg) v%i(k)
              case ('l')
                read(rest, *, iostat=ios, iomsg=msg) v%l(k)
              end select
            end if
            pos = pos + 1
          end do
        end do
      end do
    end associate
  end subroutine parse_values

  !> A variable given twice in one group without a subscript (namelist input keeps the last
  !! value, which an edit of the first would not change): a warning at the later line.
  subroutine warn_repeated(rd, io)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    integer :: ia, ib
    associate (o => rd%occ(io))
      do ia = 2, o%n_asg
        if (o%asg(ia)%stray .or. len(o%asg(ia)%sub) > 0) cycle
        do ib = 1, ia - 1
          if (o%asg(ib)%stray .or. len(o%asg(ib)%sub) > 0) cycle
          if (o%asg(ib)%base /= o%asg(ia)%base) cycle
          call add_warn(rd, o%asg(ia)%line, label(rd, io)//': '//o%asg(ia)%base//' = '// &
            o%asg(ia)%value//': given again (first on line '//itoa(o%asg(ib)%line)// &
            '); the last value is used')
          exit
        end do
      end do
    end associate
  end subroutine warn_repeated

  !> Check names, subscripts, value types and value counts of every assignment in a group.
  !! Like gfortran's namelist reader, a text value without quotes that starts with a digit
  !! (`model = 3.5`) is read as text, unless strict: then, as when the reader fails on the
  !! group for another reason, it is reported too.
  subroutine diagnose(rd, io, strict)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    logical, intent(in) :: strict
    integer :: ia, vi
    character(len=:), allocatable :: written
    do ia = 1, rd%occ(io)%n_asg
      if (rd%occ(io)%asg(ia)%stray) then
        call add_err(rd, rd%occ(io)%asg(ia)%line, label(rd, io)//': unexpected text '''// &
          rd%occ(io)%asg(ia)%value//''' (expected <name> = <value>)'// &
          missing_equals(rd%occ(io)%tok(rd%occ(io)%asg(ia)%t1)%text, rd%occ(io)%group)// &
          '; allowed: '// &
          var_list(rd%occ(io)%group))
        cycle
      end if
      vi = spec_index(rd%occ(io)%group, rd%occ(io)%asg(ia)%base)
      if (vi == 0) then
        written = rd%occ(io)%tok(rd%occ(io)%asg(ia)%t1 - 2)%text
        call add_err(rd, rd%occ(io)%asg(ia)%line, label(rd, io)//': '//written//' = '// &
          rd%occ(io)%asg(ia)%value//': unknown variable'// &
          suggestion(rd%occ(io)%asg(ia)%base, var_names(rd%occ(io)%group))//'; allowed: '// &
          var_list(rd%occ(io)%group))
        cycle
      end if
      call check_values(rd, io, ia, vi, strict)
    end do
  end subroutine diagnose

  !> Subscript, types and count of the values of assignment ia (variable vi).
  subroutine check_values(rd, io, ia, vi, strict)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, ia
    logical, intent(in) :: strict
    integer, intent(in) :: vi                !! row of the table
    character(len=1) :: kind
    integer :: cap, i1, i2, p, ios, it, r, count, ln
    character(len=:), allocatable :: name, sub, t, rest, head, what
    real(wp) :: x
    integer :: n
    logical :: l
    character(len=256) :: msg
    name = trim(specs(vi)%name)
    kind = specs(vi)%kind
    if (kind == 'e') kind = 'c'
    sub = rd%occ(io)%asg(ia)%sub
    ln = rd%occ(io)%asg(ia)%line
    cap = specs(vi)%n
    head = label(rd, io)//': '//name
    if (len(sub) > 0) head = head//'('//sub//')'
    head = head//' = '//rd%occ(io)%asg(ia)%value//': '
    if (len(sub) > 0) then
      p = index(sub, ':')
      i1 = -1
      i2 = -1
      if (p == 0) then
        read(sub, *, iostat=ios, iomsg=msg) i1
        i2 = i1
      else
        read(sub(1:p-1), *, iostat=ios, iomsg=msg) i1
        if (ios == 0) read(sub(p+1:), *, iostat=ios, iomsg=msg) i2
      end if
      if (index(sub, ',') > 0) ios = 1               ! one index only: these are 1-D
      if (ios /= 0 .or. i1 < 1 .or. i2 < i1 .or. i2 > cap) then
        if (cap == 1) then
          call add_err(rd, ln, head//'subscript on a single value; allowed: '//name// &
            ' = <value>, '//allowed_text(rd%occ(io)%group, name))
        else
          call add_err(rd, ln, head//'subscript out of range; allowed: '//name//'(1) to '// &
            name//'('//itoa(cap)//'), '//allowed_text(rd%occ(io)%group, name))
        end if
        return
      end if
      cap = i2 - i1 + 1
    end if
    count = 0
    do it = rd%occ(io)%asg(ia)%t1, rd%occ(io)%asg(ia)%t2
      t = rd%occ(io)%tok(it)%text
      count = count + nulls(rd%occ(io)%tok(it)%commas, it == rd%occ(io)%asg(ia)%t1)
      if (it < rd%occ(io)%asg(ia)%t2 .and. rd%occ(io)%tok(it)%comma_comment) then
        call add_err(rd, rd%occ(io)%tok(it)%line, head//'a comment follows the comma after '''// &
          t//''' while the values go on on the next line (gfortran cannot read that); '// &
          'allowed: no comment there, or no comma before it')
        return
      end if
      if (rd%occ(io)%tok(it)%kind == tk_string) then
        if (kind == 'c') then
          count = count + 1
          cycle
        end if
        call add_err(rd, rd%occ(io)%tok(it)%line, head//t//' is text in quotes, not '// &
          kind_text(kind)//'; allowed: '//allowed_text(rd%occ(io)%group, name))
        return
      end if
      if (kind == 'c' .and. .not. strict .and. bare_text(rd, io, it)) then
        count = count + 1
        cycle
      else if (kind == 'c') then
        call add_err(rd, rd%occ(io)%tok(it)%line, head//'text values need quotes ('// &
          name//' = '''//t//''')'//missing_equals(t, rd%occ(io)%group)//'; allowed: '// &
          allowed_text(rd%occ(io)%group, name))
        return
      end if
      call split_repeat(t, r, rest)
      if (len(rest) > 0) then
        select case (kind)
        case ('r')
          read(rest, *, iostat=ios, iomsg=msg) x
        case ('i')
          read(rest, *, iostat=ios, iomsg=msg) n
        case default
          read(rest, *, iostat=ios, iomsg=msg) l
        end select
        if (ios /= 0) then
          what = ''''//rest//''' is not '//kind_text(kind)
          if (kind == 'i') what = ''''//rest//''' is not an integer (or is too large)'
          call add_err(rd, rd%occ(io)%tok(it)%line, head//what// &
            missing_equals(rest, rd%occ(io)%group)// &
            '; allowed: '//allowed_text(rd%occ(io)%group, name))
          return
        end if
      end if
      count = count + r
    end do
    if (count > cap) then
      call add_err(rd, ln, head//'too many values ('//itoa(count)//' given, '//itoa(cap)// &
        ' allowed); allowed: '//allowed_text(rd%occ(io)%group, name))
    end if
  end subroutine check_values

  !> Null values before a value token that follows `commas` commas: each comma after '=' is
  !! one (`x = , 2`), and each comma but the first between two values (`x = 1, , 3`).
  pure integer function nulls(commas, first)
    integer, intent(in) :: commas
    logical, intent(in) :: first     !! the first value token of the assignment
    if (first) then
      nulls = commas
    else
      nulls = max(commas - 1, 0)
    end if
  end function nulls

  !> Whether gfortran's namelist reader takes word token it as a text value without quotes:
  !! it starts with a digit, has no repeat count, and no '!' or quote follows it directly
  !! (those the reader would take into the text, and then fail).
  logical function bare_text(rd, io, it)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io, it
    character(len=:), allocatable :: t
    integer :: il
    t = rd%occ(io)%tok(it)%text
    il = rd%occ(io)%tok(it)%line
    bare_text = index('0123456789', t(1:1)) > 0 .and. index(t, '*') == 0
    if (bare_text) bare_text = index(rd%lines(il)%s, t//'!') == 0 .and. &
      index(rd%lines(il)%s, t//'''') == 0 .and. index(rd%lines(il)%s, t//'"') == 0
  end function bare_text

  !> ' (is a ''='' missing after x?)' when word t is a variable name of the group.
  !> A value token as namelist input writes it: 'r*value' gives the repeat count r and the
  !! value (empty for 'r*', r null values); any other token is itself once.
  pure subroutine split_repeat(t, r, rest)
    character(len=*), intent(in) :: t      !! the token
    integer, intent(out) :: r              !! repeat count
    character(len=:), allocatable, intent(out) :: rest  !! the value
    integer :: p, ios
    r = 1
    rest = t
    p = index(t, '*')
    if (p <= 1) return
    if (verify(t(1:p-1), '0123456789') /= 0) return
    read(t(1:p-1), *, iostat=ios) r
    if (ios /= 0) r = 1
    rest = t(p+1:)
  end subroutine split_repeat

  pure function missing_equals(t, group) result(s)
    character(len=*), intent(in) :: t, group
    character(len=:), allocatable :: s
    s = ''
    if (spec_index(group, lower(t)) > 0) s = ' (is a ''='' missing after '''//t//'''?)'
  end function missing_equals

  pure function kind_text(kind) result(s)
    character(len=1), intent(in) :: kind
    character(len=:), allocatable :: s
    select case (kind)
    case ('r')
      s = 'a real number'
    case ('i')
      s = 'an integer'
    case ('l')
      s = 'a logical (.true. or .false.)'
    case default
      s = 'text in quotes'
    end select
  end function kind_text

  ! ------------------------------------------------------------------------ validators

  !> Number of table entries given (leading, without gaps); reports gaps and non-finite values.
  subroutine table_count(rd, io, var, t, n, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: t(:)
    integer, intent(out) :: n
    logical, intent(inout) :: ok
    integer :: k, last
    n = 0
    last = 0
    do k = 1, size(t)
      if (.not. finite(t(k))) then
        call err_var(rd, io, var, fmt_real(t(k)), var//'('//itoa(k)//') is not a finite number')
        ok = .false.
        return
      end if
      if (t(k) /= unset_real) last = k
    end do
    do k = 1, last
      if (t(k) == unset_real) then
        call err_var(rd, io, var, fmt_list(t(1:last)), var//'('//itoa(k)// &
          ') not given (a gap in the table)')
        ok = .false.
        return
      end if
    end do
    n = last
  end subroutine table_count

  !> `file:line: &group #k: var = value: what; allowed: ...` for occurrence io; the line and
  !! the value are those of the variable's assignment when the file has one.
  subroutine err_var(rd, io, var, value, what, allowed)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var, value, what
    character(len=*), intent(in), optional :: allowed
    integer :: ln
    character(len=:), allocatable :: v, al, shown
    call var_where(rd, io, var, value, ln, v, shown)
    ! given by subscript or with null values (', 2'): the whole value it makes too
    if (len(value) > 0 .and. (shown /= var .or. index(', '//v, ', ,') > 0)) &
      v = v//' (so '//var//' = '//value//')'
    if (present(allowed)) then
      al = allowed
    else
      al = allowed_text(rd%occ(io)%group, var)
    end if
    call add_err(rd, ln, label(rd, io)//': '//shown//' = '//v//': '//what//'; allowed: '//al)
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

  !> A warning about a variable of occurrence io.
  subroutine warn_var(rd, io, var, what)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var, what
    integer :: ln
    character(len=:), allocatable :: v, shown
    call var_where(rd, io, var, '', ln, v, shown)
    if (len(v) > 0) then
      call add_warn(rd, ln, label(rd, io)//': '//shown//' = '//v//': '//what)
    else
      call add_warn(rd, ln, label(rd, io)//': '//shown//': '//what)
    end if
  end subroutine warn_var

  !> A warning about occurrence io as a whole.
  subroutine warn_group(rd, io, what)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: what
    call add_warn(rd, rd%occ(io)%line, label(rd, io)//': '//what)
  end subroutine warn_group

  ! ------------------------------------------------ the table's checks, row by row

  !> Check every row of occurrence io against the table and store each usable value given
  !! through its field: reals (chk_r, chk_v), integers given when required and >= lo, texts
  !! given when required and not too long, names of a list (case-insensitive; stored as the
  !! list spells them, with their code). Left to the group's own rules: rows marked `own`.
  !! Rows `only` for another body shape or material model than the one given (the row `shape` or
  !! `model` comes first) are not stored, and a warning names those given.
  subroutine store_rows(rd, io, v, f)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(in) :: v
    type(field_t), intent(in) :: f(n_specs)   !! bind_fields of the record to fill
    integer, allocatable :: idx(:), other(:)
    integer :: j, r, id, n
    character(len=name_len) :: shape     ! the value of `shape` or `model` (rows `only`)
    character(len=5) :: sel              ! which of them
    character(len=:), allocatable :: name, t
    character(len=name_len), allocatable :: names(:)
    allocate(idx, source=group_specs(v%group))
    shape = ''
    sel = ''
    allocate(other(0))
    do j = 1, size(idx)
      r = idx(j)
      associate (sp => specs(r))
        name = trim(sp%name)
        if (.not. for_shape(sp%only, shape)) then
          if (row_given(v, r)) other = [other, r]
          cycle
        end if
        if (sp%own) cycle
        t = trim(adjustl(v%c(r)))
        select case (sp%kind)
        case ('r')
          if (sp%n == 1) then
            if (chk_r(rd, io, v, name)) f(r)%x = v%r(1, r)
          else if (chk_v(rd, io, v, name) == 2) then
            f(r)%v = v%r(1:2, r)
          end if
        case ('i')
          n = v%i(r)
          if (n == iunset) then
            if (sp%required) call err_missing(rd, io, name)
          else if (n < nint(max(sp%lo, -1.0e9_wp))) then
            call err_var(rd, io, name, itoa(n), 'out of range')
          else
            f(r)%i = n
          end if
        case ('l')
          f(r)%l = v%l(r)
        case ('c')
          if (sp%required .and. len(t) == 0) then
            call err_missing(rd, io, name)
          else if (len(t) > sp%max_len) then
            call err_var(rd, io, name, quote(t), 'too long ('//itoa(len(t))//' characters)')
          else
            f(r)%c = t
          end if
        case ('e')
          if (sp%c_blank .and. len(t) == 0) cycle
          names = enum_names(name)
          id = 0
          do n = 1, size(names)
            if (lower(t) == trim(names(n))) id = n
          end do
          if (id == 0) then
            call err_var(rd, io, name, quote(t), 'not an allowed value'// &
              suggestion(lower(t), names))
          else
            f(r)%c = names(id)
            f(r)%i = id
            if (name == 'shape' .or. name == 'model') shape = names(id)
            if (name == 'shape' .or. name == 'model') sel = name
          end if
        end select
      end associate
    end do
    if (size(other) > 0 .and. len_trim(shape) > 0) then
      names = specs(other)%name
      call warn_group(rd, io, join_list(names, '')//trim(merge(' is ignored ', ' are ignored', &
                      size(other) == 1))//' for '//sel//' = '''//trim(shape)//'''')
    end if
  end subroutine store_rows

  !> Whether a row `only` for the shapes in `only` (blank-separated; '' = all) applies to
  !! `shape` ('' before the shape is known: every row applies).
  pure logical function for_shape(only, shape)
    character(len=*), intent(in) :: only, shape
    for_shape = len_trim(only) == 0 .or. len_trim(shape) == 0
    if (.not. for_shape) for_shape = index(' '//trim(only)//' ', ' '//trim(shape)//' ') > 0
  end function for_shape

  !> Whether row r was given: its value differs from the value the reader starts from.
  pure logical function row_given(v, r)
    type(values_t), intent(in) :: v          !! the values of an occurrence
    integer, intent(in) :: r                 !! a row of the table
    row_given = len_trim(v%c(r)) > 0 .and. (specs(r)%c_blank .or. v%c(r) /= specs(r)%c0)
    if (specs(r)%kind == 'r') row_given = any(v%r(1:specs(r)%n, r) /= specs(r)%r0)
    if (specs(r)%kind == 'i') row_given = v%i(r) /= specs(r)%i0
    if (specs(r)%kind == 'l') row_given = v%l(r) .neqv. specs(r)%l0
  end function row_given

  !> The values of a record through its fields, as the reader would store them (names of
  !! list variables from their codes; whole numbers as reals); idx: the group's rows.
  subroutine fields_values(f, idx, v)
    type(field_t), intent(in) :: f(n_specs)
    integer, intent(in) :: idx(:)
    type(values_t), intent(inout) :: v
    integer :: j, r
    character(len=name_len), allocatable :: names(:)
    do j = 1, size(idx)
      r = idx(j)
      if (associated(f(r)%x)) v%r(1, r) = f(r)%x
      if (associated(f(r)%v)) v%r(1:size(f(r)%v), r) = f(r)%v
      if (associated(f(r)%iv)) v%r(1:size(f(r)%iv), r) = real(f(r)%iv, wp)
      if (associated(f(r)%i)) v%i(r) = f(r)%i
      if (associated(f(r)%l)) v%l(r) = f(r)%l
      if (associated(f(r)%c)) v%c(r) = f(r)%c
      if (specs(r)%kind /= 'e') cycle
      names = enum_names(trim(specs(r)%name))
      if (f(r)%i >= 1 .and. f(r)%i <= size(names)) v%c(r) = names(f(r)%i)
    end do
  end subroutine fields_values

  ! ------------------------------------------------ the table's checks, by variable name

  !> Check real `name` of v against its row: finite, given when required (the row's, or
  !! `required` when present), in range. True when usable and given.
  logical function chk_r(rd, io, v, name, required) result(good)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(in) :: v
    character(len=*), intent(in) :: name
    logical, intent(in), optional :: required
    integer :: k
    logical :: bad
    real(wp) :: x, lo, hi
    character(len=:), allocatable :: var
    k = spec_index(v%group, name)
    var = trim(specs(k)%name)
    x = v%r(1, k)
    lo = specs(k)%lo
    hi = specs(k)%hi
    good = .false.
    if (.not. finite(x)) then
      call err_var(rd, io, var, fmt_real(x), 'not a finite number')
    else if (x == unset_real) then
      if (merge_opt(required, specs(k)%required)) call err_missing(rd, io, var)
    else
      bad = .not. (x >= lo) .or. .not. (x <= hi)
      if (specs(k)%lo_open) bad = bad .or. .not. (x > lo)
      if (specs(k)%hi_open) bad = bad .or. .not. (x < hi)
      if (bad) call err_var(rd, io, var, fmt_real(x), 'out of range')
      good = .not. bad
    end if
  end function chk_r

  !> Check 2-vector `name` of v: finite, both components or none. Returns 2 (given), 0 (not
  !! given; reported when required: the row's, or `required` when present) or -1 (error
  !! reported).
  integer function chk_v(rd, io, v, name, required) result(n_given)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(in) :: v
    character(len=*), intent(in) :: name
    logical, intent(in), optional :: required
    integer :: k
    real(wp) :: x(2)
    k = spec_index(v%group, name)
    x = v%r(1:2, k)
    n_given = -1
    if (.not. all(finite(x))) then
      call err_var(rd, io, trim(specs(k)%name), fmt_vec(x), 'not finite numbers')
      return
    end if
    n_given = count(x /= unset_real)
    if (n_given == 1) then
      call err_var(rd, io, trim(specs(k)%name), fmt_vec(x), 'needs 2 values, only one was given')
      n_given = -1
    else if (n_given == 0 .and. merge_opt(required, specs(k)%required)) then
      call err_missing(rd, io, trim(specs(k)%name))
    else if (n_given == 2 .and. (any(x < specs(k)%lo) .or. any(x > specs(k)%hi) .or. &
             (specs(k)%lo_open .and. any(x <= specs(k)%lo)))) then
      call err_var(rd, io, trim(specs(k)%name), fmt_vec(x), 'out of range')
      n_given = -1
    end if
  end function chk_v

  !> The optional flag when present, else the default.
  pure logical function merge_opt(flag, default)
    logical, intent(in), optional :: flag
    logical, intent(in) :: default
    merge_opt = default
    if (present(flag)) merge_opt = flag
  end function merge_opt

  ! ------------------------------------------------------------------------ accessors

  real(wp) function vreal(v, name)
    type(values_t), intent(in) :: v
    character(len=*), intent(in) :: name
    vreal = v%r(1, spec_index(v%group, name))
  end function vreal

  function vvec(v, name) result(x)
    type(values_t), intent(in) :: v
    character(len=*), intent(in) :: name
    real(wp) :: x(2)
    x = v%r(1:2, spec_index(v%group, name))
  end function vvec

  function vtab(v, name) result(x)
    type(values_t), intent(in) :: v
    character(len=*), intent(in) :: name
    real(wp) :: x(max_table)
    x = v%r(1:max_table, spec_index(v%group, name))
  end function vtab

  integer function vint(v, name)
    type(values_t), intent(in) :: v
    character(len=*), intent(in) :: name
    vint = v%i(spec_index(v%group, name))
  end function vint

  function vtext(v, name) result(s)
    type(values_t), intent(in) :: v
    character(len=*), intent(in) :: name
    character(len=long_len) :: s
    s = v%c(spec_index(v%group, name))
  end function vtext

end module mpm_config_values
