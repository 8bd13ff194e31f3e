!> The case read from one namelist file: the pre-scan (mpm_config_scan), the compiler's namelist
!! read of every assignment (mpm_config_record), the checks of each variable against its row of
!! the table (mpm_config_table), the group rules and those across groups (mpm_config_check,
!! a body's in mpm_config_body),
!! every problem reported at once; and the public face of the input (types, echo, defaults).
! SPDX-License-Identifier: MIT
module mpm_config
  use, intrinsic :: ieee_exceptions, only: ieee_overflow, ieee_get_halting_mode, &
                                           ieee_set_halting_mode, ieee_get_flag, ieee_set_flag
  use mpm_kinds, only: wp
  use mpm_constants, only: EXIT_INPUT, EXIT_IO, BASIS_CPDI2, SCHEME_MUSL, PLANE_STRAIN, &
                           MODEL_J2, RATE_NONE, FLOW_LINEAR, SHAPE_RING, SECTOR_FULL, &
                           CONTACT_FRICTIONLESS
  use mpm_config_types, only: config_t, unset_real, scene_of, stiffest_penalty
  use mpm_config_text, only: lower, itoa, quote, unquote, suggestion, join_list, fmt_list, finite
  use mpm_config_table, only: specs, n_groups, group_names, group_id, spec_index, group_specs, &
                              var_names, enum_names, beyond
  use mpm_config_record, only: rec_t, field_t, record_read, record_fields, field_index, field_text
  use mpm_config_scan, only: reader_t, load_lines, scan_source, check_groups, add_err, &
                             add_warn, join_msgs, label, err_var, err_missing, warn_group, &
                             given, last_asg, value_tokens, allowed_text, tok_len
  use mpm_config_check, only: check_group, cross_checks, unit_checks
  use mpm_config_body, only: check_mesh
  use mpm_config_echo, only: write_config, write_config_unit
  implicit none
  private
  public :: config_t, read_config, config_resolve, write_config, write_config_unit, default_config
  public :: scene_of, stiffest_penalty

contains

  !> Read, default, validate. On stat /= 0, errmsg holds one line per problem, each naming the
  !! file, the line (where there is one), the group, the variable, the value and what is allowed.
  subroutine read_config(path, cfg, stat, errmsg, warnings)
    character(len=*), intent(in) :: path                   !! namelist file
    type(config_t), intent(out) :: cfg                     !! the case (undefined when stat /= 0)
    integer, intent(out) :: stat                           !! 0 ok, else EXIT_INPUT or EXIT_IO
    character(len=:), allocatable, intent(out) :: errmsg   !! all problems, one per line
    character(len=:), allocatable, intent(out), optional :: warnings !! advice, one per line
    type(reader_t) :: rd
    integer :: u, ios
    character(len=512) :: iomsg
    logical :: is_dir
    character(len=:), allocatable :: warn
    stat = EXIT_IO
    errmsg = 'no input file name given; give the path of a .nml file'
    if (len_trim(path) == 0) return
    errmsg = trim(path)//': is a folder, not a namelist file; give the path of a .nml file'
    inquire(file=trim(path)//'/.', exist=is_dir, iostat=ios, iomsg=iomsg)
    if (ios == 0 .and. is_dir) return
    open(newunit=u, file=path, status='old', action='read', form='formatted', &
         access='sequential', iostat=ios, iomsg=iomsg)
    errmsg = trim(path)//': cannot open the input file ('//trim(iomsg)// &
             '); check the file name and that the file is readable'
    if (ios /= 0) return
    call load_lines(rd, u, ios, iomsg)
    close(u)
    errmsg = trim(path)//': cannot read the input file ('//trim(iomsg)//')'
    if (ios /= 0) return
    rd%file = trim(path)
    call read_lines(rd, cfg, stat, errmsg, warn)
    if (present(warnings)) call move_alloc(warn, warnings)
  end subroutine read_config

  !> Validate a case built in code (tests, bench, tools) with the rules and messages of the
  !! input file, and resolve it as read_config would (names from codes, defaults that depend
  !! on other groups, material references): its echo is read back. Messages name cfg%file (or
  !! 'config') without a line.
  subroutine config_resolve(cfg, stat, errmsg, warnings)
    type(config_t), intent(inout) :: cfg                   !! in: as built; out: resolved
    integer, intent(out) :: stat                           !! 0 ok, else EXIT_INPUT
    character(len=:), allocatable, intent(out) :: errmsg   !! all problems, one per line
    character(len=:), allocatable, intent(out), optional :: warnings !! advice, one per line
    type(reader_t) :: rd
    type(config_t) :: out
    integer :: u, ios
    character(len=512) :: iomsg
    character(len=:), allocatable :: warn
    stat = EXIT_IO
    open(newunit=u, status='scratch', action='readwrite', form='formatted', iostat=ios, &
         iomsg=iomsg)
    errmsg = 'config_resolve: no scratch file ('//trim(iomsg)//')'
    if (ios /= 0) return
    call write_config_unit(cfg, u, stat, errmsg)
    rewind(u)
    if (stat == 0) call load_lines(rd, u, stat, iomsg)
    close(u)
    if (stat /= 0) return
    rd%file = trim(cfg%file)
    if (len(rd%file) == 0) rd%file = 'config'
    rd%numbered = .false.
    call read_lines(rd, out, stat, errmsg, warn)
    if (present(warnings)) call move_alloc(warn, warnings)
    if (stat /= 0) return
    out%file = cfg%file
    cfg = out
  end subroutine config_resolve

  !> read_config on the lines in rd, with floating-point overflow traps held off (a number
  !! too large for a double, 1e400, reads as Infinity and is reported).
  subroutine read_lines(rd, cfg, stat, errmsg, warnings)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(out) :: cfg
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg, warnings
    logical :: halting, flag
    call ieee_get_halting_mode(ieee_overflow, halting)
    call ieee_get_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, .false.)
    call read_all(rd, cfg)
    call ieee_set_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, halting)
    stat = merge(EXIT_INPUT, 0, rd%n_err > 0)
    errmsg = join_msgs(rd%err)
    warnings = join_msgs(rd%warn)
  end subroutine read_lines

  !> Scan, read each group occurrence into its record, check it and store it in cfg; then the
  !! checks across groups.
  subroutine read_all(rd, cfg)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(out) :: cfg
    integer :: jo, io, ig, k, n0, n1, n_of(n_groups), first_of(n_groups)
    integer, allocatable :: occ(:,:), order(:)
    type(rec_t) :: rec
    cfg%file = rd%file
    call scan_source(rd)
    rd%n_occ = size(rd%occ)
    if (rd%n_occ == 0 .and. rd%n_err == 0) then
      call add_err(rd, 0, 'the file is empty (no namelist groups); required: &run, &grid, '// &
        'at least one &material and one &body (tubempm --defaults prints a template)')
      return
    end if
    call check_groups(rd, n_of, first_of)
    allocate(cfg%materials(n_of(4)), cfg%bodies(n_of(5)), cfg%walls(n_of(6)), &
             cfg%probes(n_of(7)), cfg%contacts(n_of(8)), occ(maxval(n_of), n_groups))
    occ = 0
    order = [(io, io = 1, rd%n_occ)]         ! &run first: its check_units holds for the others
    order = [pack(order, [(rd%occ(io)%group == 'run', io = 1, rd%n_occ)]), &
             pack(order, [(rd%occ(io)%group /= 'run', io = 1, rd%n_occ)])]
    do jo = 1, rd%n_occ
      io = order(jo)
      ig = group_id(rd%occ(io)%group)
      if (ig == 0) cycle
      k = rd%occ(io)%index
      occ(k, ig) = io
      if (.not. rd%occ(io)%readable) then
        rd%occ(io)%ok = .false.
        cycle
      end if
      n0 = rd%n_err
      call read_occurrence(rd, io, ig, rec)
      if (rd%occ(io)%read_ok) call check_rows(rd, io, ig, rec)
      select case (ig)
      case (1); cfg%run = rec%run
      case (2); cfg%solver = rec%solver
      case (3); cfg%grid = rec%grid
      case (4); cfg%materials(k) = rec%material
      case (5); cfg%bodies(k)%body_in_t = rec%body
      case (6); cfg%walls(k) = rec%wall
      case (7); cfg%probes(k) = rec%probe
      case (8); cfg%contacts(k) = rec%contact
      end select
      n1 = rd%n_err                          ! a value in a likely wrong unit first: the
      if (rd%occ(io)%read_ok .and. n1 == n0 .and. cfg%run%check_units) &  ! rules would blame
        call unit_checks(rd, cfg, io)        ! another variable for it
      if (rd%occ(io)%read_ok .and. rd%n_err == n1) call check_group(rd, io, ig, k, cfg)
      if (ig == 5 .and. rd%n_err == n0) call check_mesh(rd, io, cfg%bodies(k))
      rd%occ(io)%ok = rd%n_err == n0
    end do
    call cross_checks(rd, cfg, first_of, occ(1:n_of(4), 4), occ(1:n_of(5), 5), &
                      occ(1:n_of(8), 8))
  end subroutine read_all

  !> The record of group ig that starts a group: the type's defaults, the tables not given.
  function record_start(ig) result(rec)
    integer, intent(in) :: ig
    type(rec_t) :: rec
    if (ig == 4) rec%material%curve_strain = unset_real
    if (ig == 4) rec%material%curve_stress = unset_real
    if (ig == 6) rec%wall%motion_t = unset_real
    if (ig == 6) rec%wall%motion_f = unset_real
  end function record_start

  !> Read every assignment of occurrence io into rec with the compiler's namelist read; an
  !! unknown name, a subscript out of range, a text too long or a value that does not read is
  !! reported at its line (and the occurrence is not read_ok).
  subroutine read_occurrence(rd, io, ig, rec)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, ig
    type(rec_t), intent(out) :: rec
    type(field_t), allocatable :: f(:)
    integer :: ia, ib, k, r, ios, n0, i1, i2
    character(len=256) :: msg
    character(len=:), allocatable :: head, t, sub, allow
    character(len=tok_len), allocatable :: tok(:)
    rec = record_start(ig)
    allocate(f, source=record_fields(ig, rec))
    n0 = rd%n_err
    do ia = 1, rd%occ(io)%n_asg
      associate (a => rd%occ(io)%asg(ia))
        sub = ''
        if (len(a%sub) > 0) sub = '('//a%sub//')'
        head = label(rd, io)//': '//a%name//sub//' = '//a%value//': '
        r = spec_index(rd%occ(io)%group, a%name)
        if (r == 0) then
          call add_err(rd, a%line, head//'unknown variable'//suggestion(a%name, &
            var_names(rd%occ(io)%group))//'; allowed: '//join_list(var_names( &
            rd%occ(io)%group), ''))
          cycle
        end if
        head = label(rd, io)//': '//trim(specs(r)%name)//sub//' = '//a%value//': '
        allow = allowed_text(rd%occ(io)%group, a%name)
        k = field_index(f, a%name)
        i1 = 1
        i2 = f(k)%n
        if (len(a%sub) > 0) then
          i1 = -1
          read(a%sub, *, iostat=ios) i1
          if (index(a%sub, ':') > 0) read(a%sub(index(a%sub, ':') + 1:), *, iostat=ios) i2
          if (index(a%sub, ':') == 0) i2 = i1
          if (ios /= 0 .or. verify(a%sub, '0123456789: ') /= 0 .or. i1 < 1 .or. i2 < i1 .or. &
              i2 > f(k)%n) then
            if (f(k)%n == 1) then
              call add_err(rd, a%line, head//'subscript on a single value; allowed: '// &
                trim(specs(r)%name)//' = <value>, '//allow)
            else
              call add_err(rd, a%line, head//'subscript out of range; allowed: '// &
                trim(specs(r)%name)//'(1) to '//trim(specs(r)%name)//'('//itoa(f(k)%n)//'), '// &
                allow)
            end if
            cycle
          end if
        end if
        if (allocated(tok)) deallocate(tok)
        allocate(tok, source=value_tokens(a%value))
        t = 'x'
        if (size(tok) > 0) t = trim(tok(1))//'x'
        if (f(k)%kind == 'c' .and. index('''"', t(1:1)) > 0) then
          t = t(:len(t) - 1)
          if (len(unquote(t)) > f(k)%length) then
            call add_err(rd, a%line, head//'too long ('//itoa(len(unquote(t)))// &
              ' characters); allowed: '//allow)
            cycle
          end if
        end if
        call record_read(ig, rec, a%name//sub//' = '//a%value, ios, msg)
        if (ios /= 0) call bad_value(rd, io, ia, f(k), i2 - i1 + 1, head)
        do ib = 1, ia - 1                   ! a variable given twice: the last value is used
          if (len(a%sub) > 0 .or. len(rd%occ(io)%asg(ib)%sub) > 0) cycle
          if (lower(rd%occ(io)%asg(ib)%name) /= lower(a%name)) cycle
          call add_warn(rd, a%line, head//'given again (line '// &
            itoa(rd%occ(io)%asg(ib)%line)//'); the last counts. Delete one (docs/input.md#'// &
            rd%occ(io)%group//')')
          exit
        end do
      end associate
    end do
    rd%occ(io)%read_ok = rd%n_err == n0
  end subroutine read_occurrence

  !> The compiler could not read assignment ia into field f (cap values from its subscript):
  !! say which value is wrong and why, at its line, after head (`&group: var = value: `).
  subroutine bad_value(rd, io, ia, f, cap, head)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, ia, cap
    type(field_t), intent(in) :: f
    character(len=*), intent(in) :: head
    character(len=*), parameter :: kinds(4) = [character(len=29) :: 'a real number', &
      'an integer (or is too large)', 'a logical (.true. or .false.)', 'text in quotes']
    character(len=tok_len), allocatable :: tok(:)
    character(len=:), allocatable :: what, t, kind
    integer :: j, r, n, ios, ln
    real(wp) :: x
    logical :: l
    associate (a => rd%occ(io)%asg(ia), o => rd%occ(io))
      kind = trim(kinds(index('rilc', f%kind)))
      allocate(tok, source=value_tokens(a%value))
      what = ''
      ln = a%line
      n = 0
      do j = 1, size(tok)
        t = trim(tok(j))
        r = 1
        if (index(t, '*') > 1 .and. t(1:1) /= '''' .and. t(1:1) /= '"') then
          read(t(:index(t, '*') - 1), *, iostat=ios) r
          t = t(index(t, '*') + 1:)
        end if
        if (len(t) == 0) then               ! null values
          n = n + r
          cycle
        end if
        if (t(1:1) == '''' .or. t(1:1) == '"') then
          if (f%kind /= 'c') what = t//' is text in quotes, not '//kind
        else if (f%kind == 'c') then
          what = 'text values need quotes ('//trim(specs(spec_index(o%group, a%name))%name)// &
            ' = '''//t//''')'
        else if (f%kind == 'r') then
          read(t, *, iostat=ios) x
          if (ios /= 0) what = ''''//t//''' is not '//kind
        else if (f%kind == 'i') then
          read(t, *, iostat=ios) r
          if (ios /= 0) what = ''''//t//''' is not '//kind
        else
          read(t, *, iostat=ios) l
          if (ios /= 0) what = ''''//t//''' is not '//kind
        end if
        if (len(what) > 0) then
          if (spec_index(o%group, t) > 0) what = what//' (is a ''='' missing after '''//t//'''?)'
          ln = max(a%line, o%at(max(1, min(a%v0 + index(o%body(a%v0:), t) - 1, size(o%at)))))
          exit
        end if
        n = n + r
      end do
      if (len(what) == 0 .and. n > cap) what = 'too many values ('//itoa(n)//' given, '// &
        itoa(cap)//' allowed)'
      if (len(what) == 0) what = 'not '//kind
      call add_err(rd, ln, head//what//'; allowed: '//allowed_text(o%group, a%name))
    end associate
  end subroutine bad_value

  !> Every variable of occurrence io against its row: the variables of another body shape or
  !! material model are reset to their defaults (and those given are warned of); then a
  !! required one must be given, a number finite and in range, a pair given as two values, a
  !! name one of its list (stored as the list spells it, with its code). A value that fails is
  !! reset to its default, so that no later rule meets it.
  subroutine check_rows(rd, io, ig, rec)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, ig
    type(rec_t), intent(inout) :: rec
    type(field_t), allocatable :: f(:), d(:)
    integer, allocatable :: idx(:)
    integer :: j, r, k, id, n0, ios
    character(len=:), allocatable :: name, sel, other, t, lim
    character(len=64), allocatable :: names(:)
    character(len=256) :: msg
    allocate(f, source=record_fields(ig, rec))
    allocate(d, source=record_fields(ig, record_start(ig)))
    allocate(idx, source=group_specs(group_names(ig)))
    sel = ''
    other = ''
    do j = 1, size(idx)
      r = idx(j)
      name = trim(specs(r)%name)
      k = field_index(f, name)
      n0 = rd%n_err
      t = ''
      if (len(trim(specs(r)%only)) > 0 .and. len(sel) > 0 .and. &
          index(' '//trim(specs(r)%only)//' ', ' '//sel//' ') == 0) then
        if (given(rd, io, name) .and. f(k)%raw /= d(k)%raw) other = trim(other//', '//name)
        call record_read(ig, rec, name//' = '//d(k)%raw, ios, msg)
        cycle
      end if
      lim = ''                               ! beyond the program's limits (a table's: its rules)
      if (f(k)%kind == 'r' .and. f(k)%n <= 2) lim = beyond(r, f(k)%x)
      names = enum_names(name)
      if (.not. given(rd, io, name) .and. specs(r)%required) then
        call err_missing(rd, io, name)
      else if (.not. given(rd, io, name) .and. size(names) == 0) then
        continue                             ! its default
      else if (f(k)%n > 2) then
        continue                             ! a table: the group's rules
      else if (len(lim) > 0) then
        call err_var(rd, io, name, field_text(f(k)), lim)
      else if (f(k)%kind == 'r' .and. .not. all(finite(f(k)%x))) then
        call err_var(rd, io, name, field_text(f(k)), trim(merge('not a finite number', &
          'not finite numbers ', f(k)%n == 1)))
      else if (f(k)%n == 2 .and. f(k)%kind == 'r' .and. count_values(rd, io, name) == 1) then
        call err_var(rd, io, name, fmt_list(f(k)%x), 'needs 2 values, only one was given')
      else if ((f(k)%kind == 'r' .or. f(k)%kind == 'i') ) then
        if (any(.not. (f(k)%x >= specs(r)%lo .and. f(k)%x <= specs(r)%hi)) .or. &
            (specs(r)%lo_open .and. any(.not. f(k)%x > specs(r)%lo)) .or. &
            (specs(r)%hi_open .and. any(.not. f(k)%x < specs(r)%hi))) &
          call err_var(rd, io, name, field_text(f(k)), 'out of range')
      else if (f(k)%kind == 'c' ) then
        t = trim(adjustl(f(k)%s))
        id = 0
        if (size(names) > 0) id = findloc(names, lower(t), 1)
        if (specs(r)%required .and. len(t) == 0) then
          call err_missing(rd, io, name)
        else if (size(names) > 0 .and. id == 0) then
          call err_var(rd, io, name, quote(t), 'not an allowed value'// &
            suggestion(lower(t), names))
        else if (size(names) > 0) then
          call record_read(ig, rec, name//' = '''//trim(names(id))//'''', ios, msg)
          call record_read(ig, rec, name//'_id = '//itoa(id), ios, msg)
          if (name == 'shape' .or. name == 'model') sel = trim(names(id))
        else if (t /= f(k)%s) then
          call record_read(ig, rec, name//' = '//quote(t), ios, msg)
        end if
      end if
      if (rd%n_err > n0) call record_read(ig, rec, name//' = '//d(k)%raw, ios, msg)
    end do
    if (len(other) > 0) call warn_group(rd, io, other(3:)//trim(merge(' is ignored ', &
      ' are ignored', index(other(3:), ',') == 0))//' for '//trim(merge('shape', 'model', &
      ig == 5))//' = '''//sel//'''. Delete '//trim(merge('it  ', 'them', index(other(3:), ',') &
      == 0)))
  end subroutine check_rows

  !> How many values the last assignment to var gives (a null value counts, r*x counts r).
  integer function count_values(rd, io, var) result(n)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    character(len=tok_len), allocatable :: tok(:)
    integer :: j, r, ios, ia
    n = 2
    ia = last_asg(rd, io, var)
    if (ia == 0) return
    if (len(rd%occ(io)%asg(ia)%sub) > 0) return
    allocate(tok, source=value_tokens(rd%occ(io)%asg(ia)%value))
    n = 0
    do j = 1, size(tok)
      r = 1
      if (index(tok(j), '*') > 1) read(tok(j)(:index(tok(j), '*') - 1), *, iostat=ios) r
      n = n + r
    end do
  end function count_values

  !> A case with one group of each kind and every default; the required numbers are left
  !! unset (written as comments by write_config). For `tubempm --defaults`.
  subroutine default_config(cfg)
    type(config_t), intent(out) :: cfg   !! the template case
    cfg%file = ''
    cfg%solver%basis_id = BASIS_CPDI2
    cfg%solver%scheme_id = SCHEME_MUSL
    cfg%solver%plane_id = PLANE_STRAIN
    allocate(cfg%materials(1), cfg%bodies(1), cfg%walls(1), cfg%probes(1), cfg%contacts(1))
    cfg%materials(1)%model_id = MODEL_J2
    cfg%materials(1)%rate_law_id = RATE_NONE
    cfg%materials(1)%flow_stress_id = FLOW_LINEAR
    cfg%bodies(1)%shape_id = SHAPE_RING
    cfg%bodies(1)%sector_id = SECTOR_FULL
    cfg%bodies(1)%material_id = 1
    cfg%walls(1)%point = unset_real
    cfg%walls(1)%normal = unset_real
    cfg%walls(1)%contact_id = CONTACT_FRICTIONLESS
    cfg%probes(1)%point = unset_real
    cfg%contacts(1)%law_id = CONTACT_FRICTIONLESS
  end subroutine default_config
end module mpm_config
