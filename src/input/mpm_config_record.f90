!> One record of each namelist group, read and written by the compiler's namelist I/O: an
!! assignment of the input (`name = value`, in the full namelist syntax: repeat counts, null
!! values, subscripts, quotes) read into the record, and the record's values by name, taken
!! from its namelist output. So the checks and the echo need no list of the variables: the
!! types of mpm_config_types are that list.
! SPDX-License-Identifier: MIT
!
! Each group's namelist holds one object, v_<group>, of the group's type; an assignment
! `t_end = 1e-3` of &run is read as the internal file `&run v_run%t_end = 1e-3 /`. The output
! of `write(buf, nml=run)` lists every component as `V_RUN%T_END= ...` with its values, from
! which record_fields takes each component's name, kind, size, length and values.
module mpm_config_record
  use mpm_kinds, only: wp
  use mpm_config_types, only: run_cfg_t, solver_cfg_t, grid_cfg_t, material_cfg_t, body_in_t, &
                              wall_cfg_t, probe_cfg_t, contact_cfg_t
  use mpm_config_text, only: lower, string_end, unquote, itoa, fmt_real
  use mpm_config_table, only: group_names
  implicit none
  private
  public :: rec_t, field_t, record_read, record_fields, field_index, field_text

  !> A record of every group (one at a time is in use).
  type :: rec_t
    type(run_cfg_t) :: run
    type(solver_cfg_t) :: solver
    type(grid_cfg_t) :: grid
    type(material_cfg_t) :: material
    type(body_in_t) :: body
    type(wall_cfg_t) :: wall
    type(probe_cfg_t) :: probe
    type(contact_cfg_t) :: contact
  end type rec_t

  !> One component of a record as its namelist output gives it.
  type :: field_t
    character(len=32) :: name = ''          !! lower case
    character(len=1) :: kind = 'r'          !! r real, i integer, l logical, c text
    integer :: n = 0                        !! values
    integer :: length = 0                   !! text: the declared length
    character(len=:), allocatable :: raw    !! the values as written (namelist syntax)
    real(wp), allocatable :: x(:)           !! r, i: the values; l: 1 (true) or 0
    character(len=:), allocatable :: s      !! c: the text without trailing blanks
  end type field_t

contains

  !> Read one assignment (`name = values`, `name(i) = ...`, without the group's frame) of
  !! group ig into the record; ios and msg as the compiler's namelist read sets them.
  subroutine record_read(ig, rec, text, ios, msg)
    integer, intent(in) :: ig              !! group (mpm_config_table's group_names)
    type(rec_t), intent(inout) :: rec
    character(len=*), intent(in) :: text   !! the assignment
    integer, intent(out) :: ios
    character(len=*), intent(out) :: msg
    character(len=:), allocatable :: buf
    call record_io(ig, rec, .false., text, buf, ios, msg)
  end subroutine record_read

  !> The components of the record of group ig with their values.
  function record_fields(ig, rec) result(f)
    integer, intent(in) :: ig
    type(rec_t), intent(in) :: rec
    type(field_t), allocatable :: f(:)
    type(rec_t) :: r
    character(len=:), allocatable :: buf
    character(len=256) :: msg
    integer :: ios
    r = rec
    call record_io(ig, r, .true., '', buf, ios, msg)
    f = parse_fields(buf)
  end function record_fields

  !> Index of the component `name` in f (0 if none).
  pure integer function field_index(f, name) result(k)
    type(field_t), intent(in) :: f(:)
    character(len=*), intent(in) :: name
    do k = 1, size(f)
      if (f(k)%name == lower(name)) return
    end do
    k = 0
  end function field_index

  !> The values of a number field as a list ('1.0, 2.0'; integers without a point).
  function field_text(f) result(s)
    type(field_t), intent(in) :: f
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, f%n
      if (k > 1) s = s//', '
      if (f%kind == 'i') s = s//itoa(nint(f%x(k)))
      if (f%kind /= 'i') s = s//fmt_real(f%x(k))
    end do
  end function field_text

  !> The namelist read of one assignment (write = .false.) or the write of the whole record
  !! into buf (write = .true.).
  subroutine record_io(ig, rec, write, text, buf, ios, msg)
    integer, intent(in) :: ig
    type(rec_t), intent(inout) :: rec
    logical, intent(in) :: write
    character(len=*), intent(in) :: text
    character(len=:), allocatable, intent(out) :: buf
    integer, intent(out) :: ios
    character(len=*), intent(out) :: msg
    character(len=len(text) + 24) :: lines(3)
    type(run_cfg_t) :: v_run
    type(solver_cfg_t) :: v_solver
    type(grid_cfg_t) :: v_grid
    type(material_cfg_t) :: v_material
    type(body_in_t) :: v_body
    type(wall_cfg_t) :: v_wall
    type(probe_cfg_t) :: v_probe
    type(contact_cfg_t) :: v_contact
    namelist /run/ v_run
    namelist /solver/ v_solver
    namelist /grid/ v_grid
    namelist /material/ v_material
    namelist /body/ v_body
    namelist /wall/ v_wall
    namelist /probe/ v_probe
    namelist /contact/ v_contact
    msg = ''
    lines = [character(len=len(lines)) :: '&'//trim(group_names(ig)), &
             'v_'//trim(group_names(ig))//'%'//text, '/']
    allocate(character(len=32768) :: buf)
    v_run = rec%run
    v_solver = rec%solver
    v_grid = rec%grid
    v_material = rec%material
    v_body = rec%body
    v_wall = rec%wall
    v_probe = rec%probe
    v_contact = rec%contact
    select case (ig + merge(8, 0, write))
    case (1); read(lines, nml=run, iostat=ios, iomsg=msg)
    case (2); read(lines, nml=solver, iostat=ios, iomsg=msg)
    case (3); read(lines, nml=grid, iostat=ios, iomsg=msg)
    case (4); read(lines, nml=material, iostat=ios, iomsg=msg)
    case (5); read(lines, nml=body, iostat=ios, iomsg=msg)
    case (6); read(lines, nml=wall, iostat=ios, iomsg=msg)
    case (7); read(lines, nml=probe, iostat=ios, iomsg=msg)
    case (8); read(lines, nml=contact, iostat=ios, iomsg=msg)
    case (9); write(buf, nml=run, delim='apostrophe', iostat=ios, iomsg=msg)
    case (10); write(buf, nml=solver, delim='apostrophe', iostat=ios, iomsg=msg)
    case (11); write(buf, nml=grid, delim='apostrophe', iostat=ios, iomsg=msg)
    case (12); write(buf, nml=material, delim='apostrophe', iostat=ios, iomsg=msg)
    case (13); write(buf, nml=body, delim='apostrophe', iostat=ios, iomsg=msg)
    case (14); write(buf, nml=wall, delim='apostrophe', iostat=ios, iomsg=msg)
    case (15); write(buf, nml=probe, delim='apostrophe', iostat=ios, iomsg=msg)
    case (16); write(buf, nml=contact, delim='apostrophe', iostat=ios, iomsg=msg)
    end select
    rec%run = v_run
    rec%solver = v_solver
    rec%grid = v_grid
    rec%material = v_material
    rec%body = v_body
    rec%wall = v_wall
    rec%probe = v_probe
    rec%contact = v_contact
  end subroutine record_io

  !> The components of a namelist output `&G  V_G%NAME= values, ... /`: a token holding '='
  !! (outside quotes) starts a component; the values are texts in quotes or words, `r*v`
  !! standing for r copies of v.
  function parse_fields(s) result(f)
    character(len=*), intent(in) :: s
    type(field_t), allocatable :: f(:)
    type(field_t) :: one
    integer :: p, j, r, ios, n
    real(wp) :: y
    character(len=:), allocatable :: t, v
    allocate(f(0))
    n = 0
    p = index(s, ' ')
    do while (p <= len_trim(s))
      if (index(' ,', s(p:p)) > 0) then
        p = p + 1
        cycle
      end if
      if (s(p:p) == '/') exit
      if (s(p:p) == '''') then
        j = string_end(s, p)
        t = s(p:j)
      else
        j = p + scan(s(p:), ' ,=') - 2
        if (s(j+1:j+1) == '=') then                  ! a component's name
          if (n > 0) f = [f, one]
          n = n + 1
          one = field_t(name=lower(s(index(s(p:j), '%') + p:j)), raw='')
          allocate(one%x(0))
          p = j + 2
          cycle
        end if
        t = s(p:j)
      end if
      p = j + 1
      one%raw = trim(one%raw//' '//t)
      r = 1
      v = t
      if (t(1:1) /= '''' .and. index(t, '*') > 0) then
        read(t(:index(t, '*') - 1), *, iostat=ios) r
        v = t(index(t, '*') + 1:)
      end if
      one%n = one%n + r
      if (v(1:1) == '''') then
        one%kind = 'c'
        one%s = unquote(v)
        one%length = len(one%s)
        one%s = trim(one%s)
      else if (v == 'T' .or. v == 'F') then
        one%kind = 'l'
        one%x = [one%x, spread(merge(1.0_wp, 0.0_wp, v == 'T'), 1, r)]
      else
        if (verify(v, '+-0123456789') == 0) one%kind = 'i'
        read(v, *, iostat=ios) y
        one%x = [one%x, spread(y, 1, r)]
      end if
    end do
    if (n > 0) f = [f, one]
  end function parse_fields
end module mpm_config_record
