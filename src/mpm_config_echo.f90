!> The resolved input (input.nml, `tubempm --defaults`): every variable of every group with its
!! value, in the table's order and with the table's comment (meaning and unit), written so
!! that it reads back as input.
! SPDX-License-Identifier: MIT
!
! Each group is first copied into the table's value store (pack_*); the writing itself is
! generic: a required value that is not set becomes a comment, and variables that do not apply
! (ring or rectangle variables, grid bounds of a fitted grid, an empty motion table) become one
! comment line that names them.
module mpm_config_echo
  use mpm_kinds, only: wp
  use mpm_constants, only: EXIT_IO, max_table, SHAPE_RECT, basis_names, scheme_names, &
                           plane_names, model_names, rate_law_names, shape_names, sector_names, &
                           contact_names, flow_stress_names, FLOW_JOHNSON_COOK, &
                           volumetric_names, VOLUMETRIC_FBAR
  use mpm_config_types, only: config_t, run_cfg_t, solver_cfg_t, grid_cfg_t, material_cfg_t, &
                              body_cfg_t, wall_cfg_t, probe_cfg_t, contact_cfg_t, unset_real
  use mpm_config_text, only: itoa, quote, fmt_real, fill, fmt_vec, fmt_logical, finite
  use mpm_config_table, only: specs, n_specs, group_specs, echo_comment, spec_index
  use mpm_config_values, only: values_t
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
    character(len=64) :: why = ''
    integer :: n_motion = 0
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
    integer :: k
    w%unit = unit
    allocate(e)
    call w_line(w, '! tubempm input as resolved: every variable with its value (defaults '// &
      'filled in). SI units.')
    call w_line(w, '! Lines starting with ! are comments; see docs/input.md for every variable.')
    call pack_run(cfg%run, e)
    call write_group(w, e, 0)
    call pack_solver(cfg%solver, e)
    call write_group(w, e, 0)
    call pack_grid(cfg%grid, e)
    call write_group(w, e, 0)
    if (allocated(cfg%materials)) then
      do k = 1, size(cfg%materials)
        call pack_material(cfg%materials(k), e)
        call write_group(w, e, k)
      end do
    end if
    if (allocated(cfg%bodies)) then
      do k = 1, size(cfg%bodies)
        call pack_body(cfg%bodies(k), e)
        call write_group(w, e, k)
      end do
    end if
    if (allocated(cfg%walls)) then
      do k = 1, size(cfg%walls)
        if (cfg%walls(k)%mirror) cycle
        call pack_wall(cfg%walls, k, e)
        call write_group(w, e, k)
      end do
    end if
    if (allocated(cfg%probes)) then
      do k = 1, size(cfg%probes)
        call pack_probe(cfg%probes(k), e)
        call write_group(w, e, k)
      end do
    end if
    if (allocated(cfg%contacts)) then
      do k = 1, size(cfg%contacts)
        call pack_contact(cfg%contacts(k), e)
        call write_group(w, e, k)
      end do
    end if
    stat = 0
    errmsg = ''
    if (w%ios /= 0) then
      stat = EXIT_IO
      errmsg = 'cannot write the input echo ('//trim(w%iomsg)//')'
    end if
  end subroutine write_config_unit

  ! ------------------------------------------------------------ config_t into the value store

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
    select case (ig)
    case (1)
      call pack_run(cfg%run, e)
    case (2)
      call pack_solver(cfg%solver, e)
    case (3)
      call pack_grid(cfg%grid, e)
    case (4)
      call pack_material(cfg%materials(k), e)
    case (5)
      call pack_body(cfg%bodies(k), e)
    case (6)
      call pack_wall(pack(cfg%walls, .not. cfg%walls%mirror), k, e)
    case (7)
      call pack_probe(cfg%probes(k), e)
    case (8)
      call pack_contact(cfg%contacts(k), e)
    end select
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
        end if
      end associate
    end do
    v = e%v
  end subroutine config_values

  !> The name of code id in names, or text when id is not a code.
  pure function enum_name(id, names, text) result(s)
    integer, intent(in) :: id
    character(len=*), intent(in) :: names(:), text
    character(len=:), allocatable :: s
    s = text
    if (id >= 1 .and. id <= size(names)) s = trim(names(id))
  end function enum_name

  subroutine start(e, group)
    type(echo_t), intent(inout) :: e
    character(len=*), intent(in) :: group
    e%v%group = group
    e%hide = .false.
    e%silent = .false.
    e%why = ''
    e%n_motion = 0
  end subroutine start

  !> Column of variable name in the store of group e%v%group.
  integer function col(e, name)
    type(echo_t), intent(in) :: e
    character(len=*), intent(in) :: name
    col = spec_index(e%v%group, name)
  end function col

  subroutine put_r(e, name, x)
    type(echo_t), intent(inout) :: e
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: x(:)
    e%v%r(1:size(x), col(e, name)) = x
  end subroutine put_r

  subroutine put_c(e, name, s)
    type(echo_t), intent(inout) :: e
    character(len=*), intent(in) :: name, s
    e%v%c(col(e, name)) = s
  end subroutine put_c

  subroutine put_i(e, name, n)
    type(echo_t), intent(inout) :: e
    character(len=*), intent(in) :: name
    integer, intent(in) :: n
    e%v%i(col(e, name)) = n
  end subroutine put_i

  !> Leave out variables (one comment line names them and says why; no line when why is '').
  subroutine hide(e, names, why)
    type(echo_t), intent(inout) :: e
    character(len=*), intent(in) :: names(:), why
    integer :: k
    do k = 1, size(names)
      e%hide(col(e, trim(names(k)))) = .true.
    end do
    e%why = why
  end subroutine hide

  subroutine pack_run(r, e)
    type(run_cfg_t), intent(in) :: r
    type(echo_t), intent(inout) :: e
    call start(e, 'run')
    call put_c(e, 'title', r%title)
    call put_c(e, 'output_dir', r%output_dir)
    call put_r(e, 't_end', [r%t_end])
    call put_r(e, 'cfl', [r%cfl])
    call put_r(e, 'dt', [r%dt])
    call put_r(e, 'history_every', [r%history_every])
    call put_r(e, 'snapshot_every', [r%snapshot_every])
    call put_r(e, 'checkpoint_every', [r%checkpoint_every])
    call put_r(e, 'depth', [r%depth])
    call put_r(e, 'gravity', r%gravity)
    call put_i(e, 'threads', r%threads)
    e%v%l(col(e, 'mirror_images')) = r%mirror_images
    if (r%mirror_images) call hide(e, [character(len=13) :: 'mirror_images'], '')  ! the default
  end subroutine pack_run

  subroutine pack_solver(s, e)
    type(solver_cfg_t), intent(in) :: s
    type(echo_t), intent(inout) :: e
    call start(e, 'solver')
    call put_c(e, 'basis', enum_name(s%basis_id, basis_names, s%basis))
    call put_c(e, 'scheme', enum_name(s%scheme_id, scheme_names, s%scheme))
    call put_r(e, 'flip', [s%flip])
    call put_c(e, 'plane', enum_name(s%plane_id, plane_names, s%plane))
    call put_c(e, 'volumetric', enum_name(s%volumetric_id, volumetric_names, s%volumetric))
    call put_r(e, 'mass_scale', [s%mass_scale])
    call put_r(e, 'damping', [s%damping])
    e%v%l(col(e, 'deterministic')) = s%deterministic
    if (s%volumetric_id /= VOLUMETRIC_FBAR) call hide(e, ['volumetric'], '')  ! not written
  end subroutine pack_solver

  subroutine pack_grid(g, e)
    type(grid_cfg_t), intent(in) :: g
    type(echo_t), intent(inout) :: e
    call start(e, 'grid')
    call put_r(e, 'h', [g%h])
    call put_r(e, 'lower', g%lower)
    call put_r(e, 'upper', g%upper)
    if (g%fitted) call hide(e, [character(len=5) :: 'lower', 'upper'], &
      'not given, the domain is fitted around the bodies and walls')
  end subroutine pack_grid

  subroutine pack_material(m, e)
    type(material_cfg_t), intent(in) :: m
    type(echo_t), intent(inout) :: e
    call start(e, 'material')
    call put_c(e, 'name', m%name)
    call put_c(e, 'model', enum_name(m%model_id, model_names, m%model))
    call put_r(e, 'E', [m%E])
    call put_r(e, 'nu', [m%nu])
    call put_r(e, 'rho', [m%rho])
    call put_r(e, 'sigma_y', [m%sigma_y])
    call put_r(e, 'hardening', [m%hardening])
    call put_c(e, 'rate_law', enum_name(m%rate_law_id, rate_law_names, m%rate_law))
    call put_r(e, 'cs_d', [m%cs_d])
    call put_r(e, 'cs_q', [m%cs_q])
    call put_c(e, 'flow_stress', enum_name(m%flow_stress_id, flow_stress_names, m%flow_stress))
    call put_r(e, 'jc_b', [m%jc_b])
    call put_r(e, 'jc_n', [m%jc_n])
    call put_r(e, 'jc_c', [m%jc_c])
    call put_r(e, 'jc_rate0', [m%jc_rate0])
    if (m%flow_stress_id /= FLOW_JOHNSON_COOK) call hide(e, [character(len=11) :: &
      'flow_stress', 'jc_b', 'jc_n', 'jc_c', 'jc_rate0'], '')   ! the linear law: not written
  end subroutine pack_material

  subroutine pack_body(b, e)
    type(body_cfg_t), intent(in) :: b
    type(echo_t), intent(inout) :: e
    call start(e, 'body')
    call put_c(e, 'shape', enum_name(b%shape_id, shape_names, b%shape))
    call put_c(e, 'material', b%material)
    call put_r(e, 'center', b%center)
    call put_r(e, 'r_inner', [b%r_inner])
    call put_r(e, 'r_outer', [b%r_outer])
    call put_i(e, 'n_thick', b%n_thick)
    call put_i(e, 'n_circ', b%n_circ)
    call put_c(e, 'sector', enum_name(b%sector_id, sector_names, b%sector))
    e%v%l(col(e, 'self_contact')) = b%self_contact
    call put_r(e, 'size', b%size)
    call put_i(e, 'n_x', b%n_x)
    call put_i(e, 'n_y', b%n_y)
    call put_r(e, 'velocity', b%velocity)
    if (b%shape_id == SHAPE_RECT) then
      call hide(e, only_names('ring'), 'for rings only')
    else
      call hide(e, only_names('rect'), 'for rectangles only')
      if (.not. b%self_contact) e%silent(col(e, 'self_contact')) = .true.   ! the default
    end if
  end subroutine pack_body

  subroutine pack_wall(walls, k, e)
    type(wall_cfg_t), intent(in) :: walls(:)
    integer, intent(in) :: k
    type(echo_t), intent(inout) :: e
    call start(e, 'wall')
    associate (wl => walls(k))
      call put_r(e, 'point', wl%point)
      call put_r(e, 'normal', wl%normal)
      call put_c(e, 'contact', enum_name(wl%contact_id, contact_names, wl%contact))
      call put_r(e, 'friction', [wl%friction])
      call put_r(e, 'velocity', wl%velocity)
      call put_r(e, 'ramp', [wl%ramp])
      call put_r(e, 'motion_t', wl%motion_t)
      call put_r(e, 'motion_f', wl%motion_f)
      e%n_motion = wl%n_motion
    end associate
    if (e%n_motion == 0) call hide(e, [character(len=8) :: 'motion_t', 'motion_f'], &
      'no motion table')
  end subroutine pack_wall

  subroutine pack_probe(p, e)
    type(probe_cfg_t), intent(in) :: p
    type(echo_t), intent(inout) :: e
    call start(e, 'probe')
    call put_r(e, 'point', p%point)
  end subroutine pack_probe

  subroutine pack_contact(c, e)
    type(contact_cfg_t), intent(in) :: c
    type(echo_t), intent(inout) :: e
    call start(e, 'contact')
    call put_r(e, 'bodies', real(c%bodies, wp))
    call put_c(e, 'law', enum_name(c%law_id, contact_names(1:3), c%law))
    call put_r(e, 'friction', [c%friction])
  end subroutine pack_contact

  !> The body variables that belong to one shape.
  pure function only_names(shape) result(names)
    character(len=*), intent(in) :: shape
    character(len=16), allocatable :: names(:)
    integer :: k
    allocate(names(0))
    do k = 1, n_specs
      if (specs(k)%group == 'body' .and. specs(k)%only == shape) names = [names, specs(k)%name]
    end do
  end function only_names

  ! ------------------------------------------------------------------------ writing

  !> One group: header (with #k for the k-th of a repeatable group), its rows, '/'.
  subroutine write_group(w, e, k)
    type(writer_t), intent(inout) :: w
    type(echo_t), intent(in) :: e
    integer, intent(in) :: k                  !! occurrence, 0 for a single group
    integer, allocatable :: idx(:)
    integer :: j, r
    character(len=:), allocatable :: names
    call w_line(w, '')
    if (k == 0) then
      call w_line(w, '&'//trim(e%v%group))
    else
      call w_line(w, '&'//trim(e%v%group)//fill(' ', 37 - len_trim(e%v%group))//'! #'//itoa(k))
    end if
    idx = group_specs(e%v%group)
    names = ''
    do j = 1, size(idx)
      r = idx(j)
      if (e%silent(r)) cycle
      if (e%hide(r)) then                      ! a run of rows left out: one comment line
        if (len(names) > 0) names = names//', '
        names = names//trim(specs(r)%name)
        if (len_trim(e%why) == 0) then
          continue
        else if (j == size(idx)) then
          call w_line(w, '  ! '//names//': '//trim(e%why))
        else if (.not. e%hide(idx(j+1))) then
          call w_line(w, '  ! '//names//': '//trim(e%why))
        end if
        cycle
      end if
      names = ''
      if (specs(r)%n == max_table) then
        if (specs(idx(j-1))%n /= max_table) call w_line(w, '  ! motion table: '// &
          echo_comment(r)//' and '//echo_comment(idx(j+1)))
        call w_table(w, trim(specs(r)%name), e%v%r(1:e%n_motion, r))
      else if (not_set(e%v, r)) then
        call w_unset(w, trim(specs(r)%name), trim(specs(r)%unset_note))
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
        line = fill(' ', len(name) + 4)
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
    if (len(line) < 38) line = line//fill(' ', 38 - len(line))
    call w_line(w, line//' ! '//comment)
  end subroutine w_kv

  !> `  ! name = ...   ! comment` for a value that is not set.
  subroutine w_unset(w, name, comment)
    type(writer_t), intent(inout) :: w
    character(len=*), intent(in) :: name, comment
    character(len=:), allocatable :: line
    line = '  ! '//name//' = ...'
    if (len(line) < 38) line = line//fill(' ', 38 - len(line))
    call w_line(w, line//' ! '//comment)
  end subroutine w_unset

  !> A required positive number still at its type default (-1).
  elemental logical function unset_neg(x)
    real(wp), intent(in) :: x
    unset_neg = .false.
    if (finite(x)) unset_neg = x == -1.0_wp
  end function unset_neg
end module mpm_config_echo
