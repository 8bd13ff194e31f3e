!> The resolved input (input.nml, `tubempm --defaults`): every variable of every group with its
!! value, in the table's order and with the table's comment (meaning and unit), written so
!! that it reads back as input.
! SPDX-License-Identifier: MIT
!
! Each record's values come from its namelist output (mpm_config_record); a required value
! that is not set becomes a comment, and variables that do not apply (another shape's, grid
! bounds of a fitted grid, an empty motion table) become one comment line that names them.
module mpm_config_echo
  use mpm_kinds, only: wp
  use mpm_constants, only: EXIT_IO, max_table, shape_names, shape_plural, FLOW_JOHNSON_COOK, &
                           VOLUMETRIC_FBAR, MODEL_FOAM
  use mpm_config_types, only: config_t, unset_real
  use mpm_config_text, only: itoa, quote, fmt_real, finite
  use mpm_config_table, only: specs, n_groups, group_names, group_specs, echo_comment, &
                              unset_note, enum_names
  use mpm_config_record, only: rec_t, field_t, record_fields, field_index, field_text
  implicit none
  private
  public :: write_config, write_config_unit

  !> The output unit and its first write error.
  type :: writer_t
    integer :: unit = 0
    integer :: ios = 0
    character(len=512) :: iomsg = ''
  end type writer_t

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
    type(rec_t) :: rec
    integer :: ig, k, n(n_groups)
    w%unit = unit
    call w_line(w, '! tubempm input as resolved: every variable with its value (defaults '// &
      'filled in). SI units.')
    call w_line(w, '! Lines starting with ! are comments; see docs/input.md for every variable.')
    n = [1, 1, 1, 0, 0, 0, 0, 0]
    if (allocated(cfg%materials)) n(4) = size(cfg%materials)
    if (allocated(cfg%bodies)) n(5) = size(cfg%bodies)
    if (allocated(cfg%walls)) n(6) = size(cfg%walls)
    if (allocated(cfg%probes)) n(7) = size(cfg%probes)
    if (allocated(cfg%contacts)) n(8) = size(cfg%contacts)
    rec%run = cfg%run
    rec%solver = cfg%solver
    rec%grid = cfg%grid
    do ig = 1, n_groups
      do k = 1, n(ig)
        select case (ig)
        case (4); rec%material = cfg%materials(k)
        case (5); rec%body = cfg%bodies(k)%body_in_t
        case (6); rec%wall = cfg%walls(k)
        case (7); rec%probe = cfg%probes(k)
        case (8); rec%contact = cfg%contacts(k)
        end select
        if (ig == 6) then
          if (cfg%walls(k)%mirror) cycle
        end if
        call write_group(w, cfg, ig, rec, merge(0, k, ig <= 3))
      end do
    end do
    stat = 0
    errmsg = ''
    if (w%ios /= 0) then
      stat = EXIT_IO
      errmsg = 'cannot write the input echo ('//trim(w%iomsg)//')'
    end if
  end subroutine write_config_unit

  !> One group: header (with #k for the k-th of a repeatable group), its rows, '/'. The rows
  !! left out are named in one comment line per reason (none when the reason is '').
  subroutine write_group(w, cfg, ig, rec, k)
    type(writer_t), intent(inout) :: w
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: ig
    type(rec_t), intent(in) :: rec
    integer, intent(in) :: k                  !! occurrence, 0 for a single group
    type(field_t), allocatable :: f(:), d(:)
    type(rec_t) :: defaults
    integer, allocatable :: idx(:)
    logical, allocatable :: hide(:)
    character(len=64), allocatable :: why(:)
    integer :: j, n_tab, n_vert
    character(len=12) :: table
    character(len=:), allocatable :: names, name
    allocate(f, source=record_fields(ig, rec))
    allocate(d, source=record_fields(ig, defaults))
    allocate(idx, source=group_specs(group_names(ig)))
    call hidden(cfg, ig, k, idx, f, d, hide, why, n_tab, n_vert, table)
    call w_line(w, '')
    if (k == 0) then
      call w_line(w, '&'//trim(group_names(ig)))
    else
      call w_line(w, '&'//trim(group_names(ig))//repeat(' ', 37 - len_trim(group_names(ig)))// &
        '! #'//itoa(k))
    end if
    names = ''
    do j = 1, size(idx)
      name = trim(specs(idx(j))%name)
      if (hide(j)) then
        if (why(j) == '-') cycle                 ! left out without a comment line
        if (len(names) > 0) names = names//', '
        names = names//name
        if (j < size(idx)) then
          if (hide(j+1) .and. why(j+1) == why(j)) cycle
        end if
        if (len_trim(why(j)) > 0) call w_line(w, '  ! '//names//': '//trim(why(j)))
        names = ''
        cycle
      end if
      names = ''
      associate (x => f(field_index(f, name)))
        if (x%n == max_table) then
          if (f(field_index(f, trim(specs(idx(j-1))%name)))%n /= max_table) call w_line(w, &
            '  ! '//trim(table)//': '//echo_comment(idx(j))//' and '//echo_comment(idx(j+1)))
          call w_table(w, name, x%x(1:n_tab))
        else if (name == 'vertices') then
          call w_table(w, name, x%x(1:2*n_vert))
        else if (not_set(x, specs(idx(j))%unset)) then
          call w_pad(w, '  ! '//name//' = ...', unset_note(idx(j)))
        else
          call w_pad(w, '  '//name//' = '//value_text(x, f), echo_comment(idx(j)))
        end if
      end associate
    end do
    call w_line(w, '/')
  end subroutine write_group

  !> Which rows of the k-th group ig the echo leaves out, and why ('': no comment, '-': not
  !! even in a comment line); the entries of its table (a wall's motion, a foam's curve) and a
  !! tube's vertices.
  subroutine hidden(cfg, ig, k, idx, f, d, hide, why, n_tab, n_vert, table)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: ig, k, idx(:)
    type(field_t), intent(in) :: f(:), d(:)
    logical, allocatable, intent(out) :: hide(:)
    character(len=64), allocatable, intent(out) :: why(:)
    integer, intent(out) :: n_tab, n_vert
    character(len=12), intent(out) :: table
    character(len=16) :: name(size(idx))
    integer :: j, s
    name = specs(idx)%name
    allocate(hide(size(idx)), why(size(idx)))
    hide = .false.
    why = ''
    n_tab = 0
    n_vert = 0
    table = 'motion table'
    select case (ig)
    case (2)
      hide = cfg%solver%volumetric_id < VOLUMETRIC_FBAR .and. name == 'volumetric'
    case (3)
      hide = cfg%grid%fitted .and. (name == 'lower' .or. name == 'upper')
      why = 'not given, the domain is fitted around the bodies and walls'
    case (4)
      associate (m => cfg%materials(k))
        hide = m%flow_stress_id /= FLOW_JOHNSON_COOK .and. (name == 'flow_stress' .or. &
               name(:)(1:3) == 'jc_')
        n_tab = m%n_curve                    ! foam: the curve, or the law; one of nu_p, alpha
        table = 'foam curve'
        do j = 1, size(idx)
          if (specs(idx(j))%only /= 'foam') cycle
          hide(j) = m%model_id /= MODEL_FOAM .or. (name(j)(1:6) == 'curve_' .and. &
            m%n_curve == 0) .or. (name(j) == 'nu_plastic' .and. m%foam_alpha > 0.0_wp) .or. &
            (m%n_curve > 0 .and. index(' sigma_p foam_gamma foam_alpha2 foam_beta eps_d ', &
            ' '//trim(name(j))//' ') > 0)
        end do
      end associate
    case (5)
      s = cfg%bodies(k)%shape_id             ! (a record not resolved: as a ring)
      if (s < 1 .or. s > size(shape_names)) s = 1
      do j = 1, size(idx)                    ! the variables of the other shapes
        if (len_trim(specs(idx(j))%only) == 0) cycle
        if (index(' '//trim(specs(idx(j))%only)//' ', ' '//trim(shape_names(s))//' ') > 0) &
          cycle
        hide(j) = .true.
        why(j) = 'not for '//trim(shape_plural(s))
      end do
      n_vert = cfg%bodies(k)%n_vertices
      where (name == 'self_contact' .and. .not. hide .and. .not. cfg%bodies(k)%self_contact)
        hide = .true.
        why = '-'
      end where
    case (6)
      n_tab = cfg%walls(k)%n_motion
      hide = n_tab == 0 .and. (name == 'motion_t' .or. name == 'motion_f')
      why = 'no motion table'
    end select
    do j = 1, size(idx)          ! quiet rows: left out while at their default
      if (.not. (specs(idx(j))%quiet .and. f(field_index(f, trim(name(j))))%raw == &
          d(field_index(d, trim(name(j))))%raw)) cycle
      hide(j) = .true.
      why(j) = '-'                         ! (not named in the comment of those left out)
    end do
  end subroutine hidden

  !> A required value still at its type default or a "not given" mark, as the row's `unset`
  !! says: neg (-1), huge (unset_real), emp (empty text), zero.
  logical function not_set(x, unset)
    type(field_t), intent(in) :: x
    character(len=*), intent(in) :: unset
    not_set = .false.
    select case (unset)
    case ('neg')
      if (all(finite(x%x))) not_set = any(x%x == -1.0_wp)
    case ('huge')
      if (all(finite(x%x))) not_set = any(x%x == unset_real)
    case ('emp')
      not_set = len_trim(x%s) == 0
    case ('zero')
      not_set = any(x%x == 0.0_wp)
    end select
  end function not_set

  !> A value as the input writes it (a name of a list from its code).
  function value_text(x, f) result(s)
    type(field_t), intent(in) :: x            !! the field
    type(field_t), intent(in) :: f(:)         !! all fields of the record (for the code)
    character(len=:), allocatable :: s
    character(len=64), allocatable :: names(:)
    integer :: id, k
    select case (x%kind)
    case ('c')
      s = quote(trim(x%s))
      names = enum_names(trim(x%name))
      k = field_index(f, trim(x%name)//'_id')
      if (size(names) == 0 .or. k == 0) return
      id = nint(f(k)%x(1))
      if (id >= 1 .and. id <= size(names)) s = quote(trim(names(id)))
    case ('l')
      s = trim(merge('.true. ', '.false.', x%x(1) > 0.5_wp))
    case default
      s = field_text(x)
    end select
  end function value_text

  !> A table, four values per line (no comments on its lines: other namelist readers cannot
  !! read a comment after a comma when the values go on on the next line).
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

  !> `text   ! comment`, the comment from column 40.
  subroutine w_pad(w, text, comment)
    type(writer_t), intent(inout) :: w
    character(len=*), intent(in) :: text, comment
    call w_line(w, text//repeat(' ', max(0, 38 - len(text)))//' ! '//comment)
  end subroutine w_pad
end module mpm_config_echo
