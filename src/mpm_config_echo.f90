!> The resolved input (input.nml, `tubempm --defaults`): every variable of every group with its
!! value, in the table's order and with the table's comment (meaning and unit), written so
!! that it reads back as input.
! SPDX-License-Identifier: MIT
!
! Each record is read into the table's value store through its fields (mpm_config_table,
! bind_fields); the writing itself is generic: a required value that is not set becomes a
! comment, and variables that do not apply (ring or rectangle variables, grid bounds of a fitted
! grid, an empty motion table) become one comment line that names them.
module mpm_config_echo
  use mpm_kinds, only: wp
  use mpm_constants, only: EXIT_IO, max_table, shape_names, shape_plural, FLOW_JOHNSON_COOK, &
                           VOLUMETRIC_FBAR, MODEL_FOAM
  use mpm_config_types, only: config_t, unset_real
  use mpm_config_text, only: itoa, quote, fmt_real, fmt_vec, fmt_logical, finite
  use mpm_config_table, only: specs, n_specs, n_groups, group_names, group_specs, echo_comment, &
                              unset_note, field_t, bind_fields
  use mpm_config_values, only: values_t, fields_values, for_shape
  implicit none
  private
  public :: write_config, write_config_unit, config_values

  !> Accumulates formatted output and the first write error.
  type :: writer_t
    integer :: unit = 0
    integer :: ios = 0
    character(len=512) :: iomsg = ''
  end type writer_t

  !> One group as the echo writes it: its values, the rows left out and why.
  type :: echo_t
    type(values_t) :: v
    logical :: hide(n_specs) = .false.
    logical :: silent(n_specs) = .false.   ! rows left out without a comment (their default)
    character(len=64) :: why(n_specs) = ''  ! the reason a row is left out ('': no comment)
    integer :: n_motion = 0                ! entries of the table (a wall's motion, a foam curve)
    character(len=12) :: table = 'motion table'  ! its name in the comment before it
    integer :: n_vertices = 0                !! a tube's vertices (its row holds 2 per vertex)
  end type echo_t

contains


  !> Write every group as resolved (defaults filled in) to a file, readable back as input.
  subroutine write_config(cfg, path, stat, errmsg)
    type(config_t), intent(in) :: cfg                      !! the case
    character(len=*), intent(in) :: path                   !! file to write
    integer, intent(out) :: stat                           !! 0 ok, else EXIT_IO
    character(len=:), allocatable, intent(out) :: errmsg   !! the problem ('' when ok)
    integer :: u, ios
    character(len=512) :: iomsg
    open(newunit=u, file=path, status='replace', action='write', form='formatted', &
         iostat=ios, iomsg=iomsg)
    if (ios /= 0) then
      stat = EXIT_IO
      errmsg = trim(path)//': cannot create the file ('//trim(iomsg)//')'
      return
    end if
    call write_config_unit(cfg, u, stat, errmsg)
    if (stat /= 0) errmsg = trim(path)//': '//errmsg
    close(u, iostat=ios, iomsg=iomsg)
    if (ios /= 0 .and. stat == 0) then
      stat = EXIT_IO
      errmsg = trim(path)//': cannot close the file ('//trim(iomsg)//')'
    end if
  end subroutine write_config

  !> Write every group as resolved to an open formatted unit: one group per material, body,
  !! wall (mirror walls added for sectors are left out) and probe, every number in the shortest
  !! form that reads back exactly. Required values not set are written as comments.
  subroutine write_config_unit(cfg, unit, stat, errmsg)
    type(config_t), intent(in) :: cfg                      !! the case
    integer, intent(in) :: unit                            !! open formatted unit
    integer, intent(out) :: stat                           !! 0 ok, else EXIT_IO
    character(len=:), allocatable, intent(out) :: errmsg   !! the problem ('' when ok)
    type(writer_t) :: w
    type(echo_t), allocatable :: e
    integer :: ig, k, n(n_groups)
    w%unit = unit
    allocate(e)
    call w_line(w, '! tubempm input as resolved: every variable with its value (defaults '// &
      'filled in). SI units.')
    call w_line(w, '! Lines starting with ! are comments; see docs/input.md for every variable.')
    n = [1, 1, 1, 0, 0, 0, 0, 0]
    if (allocated(cfg%materials)) n(4) = size(cfg%materials)
    if (allocated(cfg%bodies)) n(5) = size(cfg%bodies)
    if (allocated(cfg%walls)) n(6) = size(cfg%walls)
    if (allocated(cfg%probes)) n(7) = size(cfg%probes)
    if (allocated(cfg%contacts)) n(8) = size(cfg%contacts)
    do ig = 1, n_groups
      do k = 1, n(ig)
        if (ig == 6) then
          if (cfg%walls(k)%mirror) cycle
        end if
        call group_echo(cfg, ig, k, e)
        call write_group(w, e, merge(0, k, ig <= 3))
      end do
    end do
    stat = 0
    errmsg = ''
    if (w%ios /= 0) then
      stat = EXIT_IO
      errmsg = 'cannot write the input echo ('//trim(w%iomsg)//')'
    end if
  end subroutine write_config_unit

  !> The k-th occurrence of group ig of cfg (walls: the k-th that is not a mirror plane) as
  !! the reader would have read it: values that are not set or do not apply hold the table's
  !! starting values (for config_resolve).
  subroutine config_values(cfg, ig, k, v)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: ig, k
    type(values_t), intent(inout) :: v
    type(echo_t), allocatable :: e
    integer, allocatable :: idx(:)
    integer :: j, r
    allocate(e)
    if (ig == 6) then
      idx = pack([(j, j = 1, size(cfg%walls))], .not. cfg%walls%mirror)
      call group_echo(cfg, ig, idx(k), e)
    else
      call group_echo(cfg, ig, k, e)
    end if
    idx = group_specs(e%v%group)
    do j = 1, size(idx)
      r = idx(j)
      associate (sp => specs(r))
        if (e%hide(r) .or. not_set(e%v, r)) then
          e%v%r(:, r) = sp%r0
          e%v%i(r) = sp%i0
          e%v%c(r) = sp%c0
          e%v%l(r) = sp%l0
          if (sp%c_blank) e%v%c(r) = ''
        else if (sp%n == max_table) then
          e%v%r(e%n_motion+1:, r) = sp%r0
        else if (sp%name == 'vertices') then
          e%v%r(2*e%n_vertices+1:, r) = sp%r0
        end if
      end associate
    end do
    v = e%v
  end subroutine config_values

  !> Record k of group ig into the value store, and the rows the echo leaves out: one comment
  !! line names them and says why (no line when why is '').
  subroutine group_echo(cfg, ig, k, e)
    type(config_t), intent(in), target :: cfg
    integer, intent(in) :: ig, k
    type(echo_t), intent(inout) :: e
    type(field_t) :: f(n_specs)
    integer, allocatable :: idx(:)
    integer :: j, r
    character(len=len(shape_names)) :: shape
    e%v%group = group_names(ig)
    e%hide = .false.
    e%silent = .false.
    e%why = ''
    e%n_motion = 0
    e%n_vertices = 0
    e%table = 'motion table'
    idx = group_specs(e%v%group)
    call bind_fields(cfg, ig, k, f)
    call fields_values(f, idx, e%v)
    select case (ig)
    case (2)
      e%hide(idx) = cfg%solver%volumetric_id < VOLUMETRIC_FBAR .and. &
                    specs(idx)%name == 'volumetric'
    case (3)
      e%hide(idx) = cfg%grid%fitted .and. specs(idx)%n == 2
      e%why = 'not given, the domain is fitted around the bodies and walls'
    case (4)
      associate (m => cfg%materials(k))
        e%hide(idx) = m%flow_stress_id /= FLOW_JOHNSON_COOK .and. &
          (specs(idx)%name == 'flow_stress' .or. specs(idx)%name(1:3) == 'jc_')
        e%n_motion = m%n_curve              ! foam: the curve, or the law; one of nu_p, alpha
        e%table = 'foam curve'
        do j = 1, size(idx)
          r = idx(j)
          if (specs(r)%only == 'foam') e%hide(r) = m%model_id /= MODEL_FOAM .or. &
            (specs(r)%n == max_table .and. m%n_curve == 0) .or. &
            (specs(r)%name == 'nu_plastic' .and. m%foam_alpha > 0.0_wp)
          if (specs(r)%only == 'foam' .and. m%n_curve > 0) e%hide(r) = e%hide(r) .or. &
            index(' sigma_p foam_gamma foam_alpha2 foam_beta eps_d ', ' '// &
                  trim(specs(r)%name)//' ') > 0
        end do
      end associate
    case (5)
      shape = shape_names(1)                 ! (a record not resolved: as a ring)
      j = cfg%bodies(k)%shape_id
      if (j >= 1 .and. j <= size(shape_names)) shape = shape_names(j)
      do j = 1, size(idx)                    ! the variables of the other shapes
        r = idx(j)
        if (for_shape(specs(r)%only, shape)) cycle
        e%hide(r) = .true.
        e%why(r) = 'not for '//trim(shape_plural(findloc(shape_names, shape, 1)))
      end do
      e%n_vertices = cfg%bodies(k)%n_vertices
      e%silent(idx) = specs(idx)%name == 'self_contact' .and. .not. e%hide(idx) .and. &
                      .not. cfg%bodies(k)%self_contact
    case (6)
      e%n_motion = cfg%walls(k)%n_motion
      e%hide(idx) = e%n_motion == 0 .and. specs(idx)%n == max_table
      e%why = 'no motion table'
    end select
    do j = 1, size(idx)          ! quiet rows: left out while at their default
      r = idx(j)
      if (.not. specs(r)%quiet) cycle
      if (specs(r)%kind == 'l') then
        e%hide(r) = e%hide(r) .or. (e%v%l(r) .eqv. specs(r)%l0)
      else
        e%hide(r) = e%hide(r) .or. e%v%r(1, r) == specs(r)%r0
      end if
    end do
  end subroutine group_echo

  ! ------------------------------------------------------------------------ writing

  !> One group: header (with #k for the k-th of a repeatable group), its rows, '/'.
  subroutine write_group(w, e, k)
    type(writer_t), intent(inout) :: w
    type(echo_t), intent(in) :: e
    integer, intent(in) :: k                  !! occurrence, 0 for a single group
    integer, allocatable :: idx(:)
    integer :: j, r
    logical :: run_ends
    character(len=:), allocatable :: names
    call w_line(w, '')
    if (k == 0) then
      call w_line(w, '&'//trim(e%v%group))
    else
      call w_line(w, '&'//trim(e%v%group)//repeat(' ', 37 - len_trim(e%v%group))//'! #'//itoa(k))
    end if
    idx = group_specs(e%v%group)
    names = ''
    do j = 1, size(idx)
      r = idx(j)
      if (e%silent(r)) cycle
      if (e%hide(r)) then                      ! a run of rows left out for one reason: one
        if (len(names) > 0) names = names//', '  ! comment line (none when the reason is '')
        names = names//trim(specs(r)%name)
        run_ends = j == size(idx)
        if (.not. run_ends) run_ends = .not. e%hide(idx(j+1)) .or. e%why(idx(j+1)) /= e%why(r)
        if (run_ends) then
          if (len_trim(e%why(r)) > 0) call w_line(w, '  ! '//names//': '//trim(e%why(r)))
          names = ''
        end if
        cycle
      end if
      names = ''
      if (specs(r)%n == max_table) then
        if (specs(idx(j-1))%n /= max_table) call w_line(w, '  ! '//trim(e%table)//': '// &
          echo_comment(r)//' and '//echo_comment(idx(j+1)))
        call w_table(w, trim(specs(r)%name), e%v%r(1:e%n_motion, r))
      else if (specs(r)%name == 'vertices') then
        call w_table(w, 'vertices', e%v%r(1:2*e%n_vertices, r))
      else if (not_set(e%v, r)) then
        call w_unset(w, trim(specs(r)%name), unset_note(r))
      else
        call w_kv(w, trim(specs(r)%name), value_text(e%v, r), echo_comment(r))
      end if
    end do
    call w_line(w, '/')
  end subroutine write_group

  !> A required value still at its type default or sentinel (as the row's `unset` says).
  logical function not_set(v, r)
    type(values_t), intent(in) :: v
    integer, intent(in) :: r
    integer :: n
    n = specs(r)%n
    select case (specs(r)%unset)
    case ('neg')
      not_set = any(unset_neg(v%r(1:n, r)))
    case ('huge')
      not_set = .false.
      if (all(finite(v%r(1:n, r)))) not_set = any(v%r(1:n, r) == unset_real)
    case ('emp')
      not_set = len_trim(v%c(r)) == 0
    case ('zero')
      not_set = v%i(r) == 0
      if (specs(r)%kind == 'r') not_set = any(v%r(1:n, r) == 0.0_wp)
    case default
      not_set = .false.
    end select
  end function not_set

  !> A value as the input writes it.
  function value_text(v, r) result(s)
    type(values_t), intent(in) :: v
    integer, intent(in) :: r
    character(len=:), allocatable :: s
    select case (specs(r)%kind)
    case ('c', 'e')
      s = quote(trim(v%c(r)))
    case ('i')
      s = itoa(v%i(r))
    case ('l')
      s = fmt_logical(v%l(r))
    case default
      if (specs(r)%whole) then
        s = itoa(nint(v%r(1, r)))//', '//itoa(nint(v%r(2, r)))
      else if (specs(r)%n == 2) then
        s = fmt_vec(v%r(1:2, r))
      else
        s = fmt_real(v%r(1, r))
      end if
    end select
  end function value_text

  !> A table, four values per line (no comments on its lines: gfortran cannot read a comment
  !! after a comma when the values go on on the next line).
  subroutine w_table(w, name, v)
    type(writer_t), intent(inout) :: w
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: v(:)
    character(len=:), allocatable :: line
    integer :: k
    line = '  '//name//' ='
    do k = 1, size(v)
      line = line//' '//fmt_real(v(k))
      if (k < size(v)) line = line//','
      if (mod(k, 4) == 0 .and. k < size(v)) then
        call w_line(w, line)
        line = repeat(' ', len(name) + 4)
      end if
    end do
    call w_line(w, line)
  end subroutine w_table

  subroutine w_line(w, text)
    type(writer_t), intent(inout) :: w
    character(len=*), intent(in) :: text
    if (w%ios /= 0) return
    write(w%unit, '(a)', iostat=w%ios, iomsg=w%iomsg) text
  end subroutine w_line

  !> `  name = value   ! comment`
  subroutine w_kv(w, name, value, comment)
    type(writer_t), intent(inout) :: w
    character(len=*), intent(in) :: name, value, comment
    character(len=:), allocatable :: line
    line = '  '//name//' = '//value
    if (len(line) < 38) line = line//repeat(' ', 38 - len(line))
    call w_line(w, line//' ! '//comment)
  end subroutine w_kv

  !> `  ! name = ...   ! comment` for a value that is not set.
  subroutine w_unset(w, name, comment)
    type(writer_t), intent(inout) :: w
    character(len=*), intent(in) :: name, comment
    character(len=:), allocatable :: line
    line = '  ! '//name//' = ...'
    if (len(line) < 38) line = line//repeat(' ', 38 - len(line))
    call w_line(w, line//' ! '//comment)
  end subroutine w_unset

  !> A required positive number still at its type default (-1).
  elemental logical function unset_neg(x)
    real(wp), intent(in) :: x
    unset_neg = .false.
    if (finite(x)) unset_neg = x == -1.0_wp
  end function unset_neg
end module mpm_config_echo
