!> The case description read from one namelist file: reading group by group, validation, the
!! checks across groups, and the public face of the input (types, echo, defaults).
! SPDX-License-Identifier: MIT
!
! The file is scanned once (mpm_config_lexer); each group occurrence is then diagnosed and read
! as the table of variables describes it (mpm_config_table, mpm_config_values), validated, and
! copied into config_t. The per-group routines below hold only what the table cannot say: how a
! value is stored, and the rules that tie variables together. config_resolve checks any
! config_t, also one built in code (tests, bench), with the same rules and messages.
module mpm_config
  use, intrinsic :: ieee_exceptions, only: ieee_overflow, ieee_get_halting_mode, &
                                           ieee_set_halting_mode, ieee_get_flag, ieee_set_flag
  use mpm_kinds, only: wp
  use mpm_constants, only: EXIT_INPUT, EXIT_IO, sector_names, BASIS_CPDI2, SCHEME_MUSL, &
                           PLANE_STRAIN, MODEL_J2, MODEL_FOAM, RATE_NONE, RATE_COWPER_SYMONDS, &
                           SHAPE_RING, SECTOR_FULL, SECTOR_HALF, SECTOR_QUARTER, max_table, &
                           CONTACT_FRICTIONLESS, CONTACT_COULOMB, CONTACT_SLIP, FLOW_LINEAR, &
                           CONTACT_BONDED, SHAPE_TUBE, SHAPE_HONEYCOMB, SHAPE_WALLS, &
                           SHAPE_DISC, max_vertices, max_cells, pi, FLOW_JOHNSON_COOK
  use mpm_config_types, only: config_t, run_cfg_t, solver_cfg_t, grid_cfg_t, material_cfg_t, &
                              body_cfg_t, wall_cfg_t, probe_cfg_t, contact_cfg_t, unset_real, &
                              iunset, scene_of
  use mpm_config_text, only: itoa, fmt_real, fmt_short, fmt_vec, fmt_list
  use mpm_config_table, only: n_groups, n_specs, group_names, group_id, field_t, bind_fields, &
                              spec_index
  use mpm_config_lexer, only: reader_t, load_lines, has_content, scan_source, check_groups, &
                              join_msgs, open_occ
  use mpm_config_values, only: values_t, read_group, store_rows, vreal, vvec, vtab, vint, &
                               chk_r, chk_v, table_count, err_var, warn_var, warn_group
  use mpm_config_check, only: cross_checks
  use mpm_config_echo, only: write_config, write_config_unit, config_values
  use mpm_bodies, only: body_mesh, is_section, body_estimate
  implicit none
  private
  public :: config_t, run_cfg_t, solver_cfg_t, grid_cfg_t, material_cfg_t, body_cfg_t, &
            wall_cfg_t, probe_cfg_t, contact_cfg_t
  public :: read_config, config_resolve, write_config, write_config_unit, default_config
  public :: unset_real, scene_of

contains

  !> Read, default, validate. On stat /= 0, errmsg holds one line per problem, each naming the
  !! file, the line (where there is one), the group, the variable, the value and what is allowed.
  !! Numbers too large for a double (1e400) are read as Infinity and reported, also when
  !! floating-point overflow traps are on (they are held off while the file is read).
  subroutine read_config(path, cfg, stat, errmsg, warnings)
    character(len=*), intent(in) :: path                   !! namelist file
    type(config_t), intent(out) :: cfg                     !! the case (undefined when stat /= 0)
    integer, intent(out) :: stat                           !! 0 ok, else EXIT_INPUT or EXIT_IO
    character(len=:), allocatable, intent(out) :: errmsg   !! all problems, one per line
    character(len=:), allocatable, intent(out), optional :: warnings !! advice, one per line
    logical :: halting, flag
    character(len=:), allocatable :: warn
    call ieee_get_halting_mode(ieee_overflow, halting)
    call ieee_get_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, .false.)
    call read_config_all(path, cfg, stat, errmsg, warn)
    call ieee_set_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, halting)
    if (present(warnings)) call move_alloc(warn, warnings)
  end subroutine read_config

  !> read_config without the floating-point mode handling.
  subroutine read_config_all(path, cfg, stat, errmsg, warnings)
    character(len=*), intent(in) :: path
    type(config_t), intent(out) :: cfg
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable, intent(out) :: warnings
    type(reader_t) :: rd
    integer :: u, ios, ios2, io, k, ig
    type(values_t), allocatable :: v
    logical :: ok
    integer :: n_of(n_groups), first_of(n_groups)
    integer, allocatable :: occ_mat(:), occ_body(:), occ_con(:)
    character(len=512) :: iomsg, iomsg2

    stat = 0
    errmsg = ''
    warnings = ''
    cfg%file = path
    rd%file = trim(path)
    allocate(rd%err(8), rd%warn(8), rd%occ(8), rd%lines(64))
    call open_input(path, u, stat, errmsg)
    if (stat /= 0) return
    call load_lines(rd, u, ios, iomsg)
    close(u, iostat=ios2, iomsg=iomsg2)
    if (ios /= 0) then
      stat = EXIT_IO
      errmsg = trim(path)//': cannot read the input file ('//trim(iomsg)//')'
      return
    end if
    if (.not. has_content(rd)) then
      stat = EXIT_INPUT
      errmsg = trim(path)//': the file is empty (no namelist groups); required: &run, &grid, '// &
               'at least one &material and one &body (tubempm --defaults prints a template)'
      return
    end if

    allocate(v)
    call scan_source(rd)
    call check_groups(rd, n_of, first_of)
    allocate(cfg%materials(n_of(4)), cfg%bodies(n_of(5)), cfg%walls(n_of(6)), &
             cfg%probes(n_of(7)), cfg%contacts(n_of(8)))
    allocate(occ_mat(n_of(4)), occ_body(n_of(5)), occ_con(n_of(8)))
    do io = 1, rd%n_occ
      k = rd%occ(io)%index
      ig = group_id(rd%occ(io)%group)
      if (ig == 4) occ_mat(k) = io
      if (ig == 5) occ_body(k) = io
      if (ig == 8) occ_con(k) = io
      if (ig == 0 .or. (ig <= 3 .and. k > 1)) cycle     ! reported by check_groups
      call read_group(rd, io, v, ok)
      if (ok) call check_group(rd, io, ig, k, v, cfg)
    end do

    call cross_checks(rd, cfg, first_of, occ_mat, occ_body, occ_con)
    if (rd%n_err > 0) then
      stat = EXIT_INPUT
      errmsg = join_msgs(rd%err, rd%n_err)
    end if
    warnings = join_msgs(rd%warn, rd%n_warn)
  end subroutine read_config_all

  !> Open the input file for reading, with a message that says what to do when it cannot be.
  subroutine open_input(path, u, stat, errmsg)
    character(len=*), intent(in) :: path
    integer, intent(out) :: u, stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: ios
    character(len=512) :: iomsg
    logical :: is_dir
    stat = EXIT_IO
    if (len_trim(path) == 0) then
      errmsg = 'no input file name given; give the path of a .nml file'
      return
    end if
    inquire(file=trim(path)//'/.', exist=is_dir, iostat=ios, iomsg=iomsg)
    if (ios == 0 .and. is_dir) then
      errmsg = trim(path)//': is a folder, not a namelist file; give the path of a .nml file'
      return
    end if
    open(newunit=u, file=path, status='old', action='read', form='formatted', &
         access='sequential', iostat=ios, iomsg=iomsg)
    if (ios /= 0) then
      errmsg = trim(path)//': cannot open the input file ('//trim(iomsg)// &
               '); check the file name and that the file is readable'
      return
    end if
    stat = 0
  end subroutine open_input

  !> Validate a case built in code (tests, bench, tools) with the rules and messages of the
  !! input file, and resolve it as read_config would: names from codes or codes from names,
  !! defaults that depend on other groups, material references. Each group is taken into the
  !! table's value store as the echo writes it; required values still at their type defaults,
  !! and values that do not apply (ring variables of a rectangle, bounds of a fitted grid,
  !! motion table entries beyond n_motion), count as not given. Messages name the group as
  !! `&material #1` with cfg%file (or 'config') in place of the file.
  subroutine config_resolve(cfg, stat, errmsg, warnings)
    type(config_t), intent(inout) :: cfg                   !! in: as built; out: resolved
    integer, intent(out) :: stat                           !! 0 ok, else EXIT_INPUT
    character(len=:), allocatable, intent(out) :: errmsg   !! all problems, one per line
    character(len=:), allocatable, intent(out), optional :: warnings !! advice, one per line
    type(reader_t) :: rd
    type(config_t) :: out
    integer :: ig, k, io, n(n_groups), first_of(n_groups)
    integer, allocatable :: occ_mat(:), occ_body(:), occ_con(:)
    type(values_t), allocatable :: v
    stat = 0
    errmsg = ''
    if (.not. allocated(cfg%contacts)) allocate(cfg%contacts(0))
    rd%file = trim(cfg%file)
    if (len(rd%file) == 0) rd%file = 'config'
    out%file = cfg%file
    allocate(rd%err(8), rd%warn(8), rd%occ(8), rd%lines(1), v)
    n = [1, 1, 1, size(cfg%materials), size(cfg%bodies), count(.not. cfg%walls%mirror), &
         size(cfg%probes), size(cfg%contacts)]
    allocate(out%materials(n(4)), out%bodies(n(5)), out%walls(n(6)), out%probes(n(7)), &
             out%contacts(n(8)), occ_mat(n(4)), occ_body(n(5)), occ_con(n(8)))
    first_of = 0
    do ig = 1, n_groups
      do k = 1, n(ig)
        call open_occ(rd, trim(group_names(ig)), 0)
        io = rd%n_occ
        if (k == 1) first_of(ig) = io
        if (ig == 4) occ_mat(k) = io
        if (ig == 5) occ_body(k) = io
        if (ig == 8) occ_con(k) = io
        call config_values(cfg, ig, k, v)
        rd%occ(io)%read_ok = .true.
        call check_group(rd, io, ig, k, v, out)
      end do
    end do
    call cross_checks(rd, out, first_of, occ_mat, occ_body, occ_con)
    if (rd%n_err > 0) then
      stat = EXIT_INPUT
      errmsg = join_msgs(rd%err, rd%n_err)
    else
      call move_alloc(out%materials, cfg%materials)
      call move_alloc(out%bodies, cfg%bodies)
      call move_alloc(out%walls, cfg%walls)
      call move_alloc(out%probes, cfg%probes)
      call move_alloc(out%contacts, cfg%contacts)
      cfg%run = out%run
      cfg%solver = out%solver
      cfg%grid = out%grid
    end if
    if (present(warnings)) warnings = join_msgs(rd%warn, rd%n_warn)
  end subroutine config_resolve

  !> Validate the values of the k-th occurrence of group ig into cfg: every row as the table
  !! says, then the rules of the group; the occurrence is ok when it added no error.
  subroutine check_group(rd, io, ig, k, v, cfg)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, ig, k
    type(values_t), intent(inout) :: v
    type(config_t), intent(inout), target :: cfg
    type(field_t) :: f(n_specs)
    integer :: n0
    n0 = rd%n_err
    call bind_fields(cfg, ig, k, f)
    call store_rows(rd, io, v, f)
    select case (ig)
    case (1)
      ! a cfl above the stability study's limit is advice (mpm_advice, --check): it depends
      ! on the basis, the scheme and the particles per cell
    case (3)
      call check_grid(rd, io, v, cfg%grid)
    case (4)
      call check_material(rd, io, v, cfg%materials(k))
    case (5)
      call check_body(rd, io, v, cfg%bodies(k))
      if (rd%n_err == n0 .and. (is_section(cfg%bodies(k)%shape_id) .or. &
          cfg%bodies(k)%shape_id == SHAPE_DISC)) call check_mesh(rd, io, cfg%bodies(k))
    case (6)
      call check_wall(rd, io, v, cfg%walls(k))
    case (8)
      call check_contact(rd, io, v, cfg%contacts(k))
    end select
    rd%occ(io)%ok = rd%n_err == n0
  end subroutine check_group

  ! ------------------------------------------------------------ the rules of the groups

  !> &grid: lower and upper, both or neither.
  subroutine check_grid(rd, io, v, g)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(inout) :: v
    type(grid_cfg_t), intent(inout) :: g
    integer :: nl, nu
    real(wp) :: lower(2), upper(2)
    nl = chk_v(rd, io, v, 'lower')
    nu = chk_v(rd, io, v, 'upper')
    lower = vvec(v, 'lower')
    upper = vvec(v, 'upper')
    g%fitted = .true.
    if (nl == 2 .and. nu == 2) then
      if (all(lower < upper)) then
        g%lower = lower
        g%upper = upper
        g%fitted = .false.
      else
        call err_var(rd, io, 'upper', fmt_vec(upper), 'not above lower = '//fmt_vec(lower)// &
          ' in both components')
      end if
    else if (nl == 2 .and. nu == 0) then
      call err_var(rd, io, 'lower', fmt_vec(lower), 'given without upper')
    else if (nu == 2 .and. nl == 0) then
      call err_var(rd, io, 'upper', fmt_vec(upper), 'given without lower')
    end if
  end subroutine check_grid

  !> &material: sigma_y (required for j2), the variables a model does not use, and the flow
  !! stress law: with Johnson-Cook (A is sigma_y) the linear law's own variables (hardening,
  !! rate_law) must be left at their defaults; the foam's variables (check_foam).
  subroutine check_material(rd, io, v, m)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(inout) :: v
    type(material_cfg_t), intent(inout) :: m
    character(len=*), parameter :: jc = 'flow_stress = ''johnson_cook'''
    character(len=:), allocatable :: not_j2
    not_j2 = 'used only by model = ''j2'' (model is '''//trim(m%model)//''')'
    if (chk_r(rd, io, v, 'sigma_y', required=m%model_id == MODEL_J2)) then
      m%sigma_y = vreal(v, 'sigma_y')
      if (m%model_id /= MODEL_J2 .and. m%model_id > 0) call warn_var(rd, io, 'sigma_y', not_j2)
    end if
    if (m%rate_law_id == RATE_COWPER_SYMONDS .and. m%model_id /= MODEL_J2) call warn_var(rd, &
      io, 'rate_law', 'used only by model = ''j2'' (it scales the yield stress)')
    if (m%flow_stress_id == FLOW_JOHNSON_COOK) then
      if (m%model_id /= MODEL_J2 .and. m%model_id > 0) call warn_var(rd, io, 'flow_stress', &
        not_j2)
      if (m%hardening > 0.0_wp) call err_var(rd, io, 'hardening', fmt_real(m%hardening), &
        'has no effect with '//jc//' (jc_b and jc_n give its hardening)', &
        '0 with '//jc//' (or flow_stress = ''linear'')')
      if (m%voce_q > 0.0_wp) call err_var(rd, io, 'voce_q', fmt_real(m%voce_q), &
        'has no effect with '//jc, '0 with '//jc//' (or flow_stress = ''linear'')')
      if (m%rate_law_id == RATE_COWPER_SYMONDS) call err_var(rd, io, 'rate_law', &
        '''cowper_symonds''', 'cannot be combined with '//jc//' (jc_c and jc_rate0 give '// &
        'its rate effect)', '''none'' with '//jc//' (or flow_stress = ''linear'')')
    else if (m%flow_stress_id == FLOW_LINEAR .and. (m%jc_b /= 0.0_wp .or. m%jc_n /= 1.0_wp &
             .or. m%jc_c /= 0.0_wp .or. m%jc_rate0 /= 1.0_wp)) then
      call warn_group(rd, io, 'jc_b, jc_n, jc_c, jc_rate0 are ignored with flow_stress = '// &
        '''linear'' (set flow_stress = ''johnson_cook'' to use them)')
    end if
    if (m%model_id == MODEL_FOAM) call check_foam(rd, io, v, m)
  end subroutine check_material

  !> &material, model = 'foam': nu_plastic or foam_alpha, not both; the hardening law
  !! (sigma_p and eps_d required) or the tabulated curve (then none of the law's variables).
  subroutine check_foam(rd, io, v, m)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(inout) :: v
    type(material_cfg_t), intent(inout) :: m
    character(len=*), parameter :: law(5) = [character(len=11) :: 'sigma_p', 'eps_d', &
      'foam_gamma', 'foam_alpha2', 'foam_beta']
    real(wp), parameter :: law_r0(5) = [unset_real, unset_real, 0.0_wp, 0.0_wp, 1.0_wp]
    real(wp) :: x(max_table), y(max_table)
    integer :: n, k, j
    logical :: ok
    if (chk_r(rd, io, v, 'nu_plastic')) m%nu_plastic = vreal(v, 'nu_plastic')
    if (chk_r(rd, io, v, 'foam_alpha')) m%foam_alpha = vreal(v, 'foam_alpha')
    if (vreal(v, 'nu_plastic') /= unset_real .and. vreal(v, 'foam_alpha') /= unset_real) &
      call err_var(rd, io, 'foam_alpha', fmt_real(vreal(v, 'foam_alpha')), 'given with '// &
        'nu_plastic = '//fmt_real(vreal(v, 'nu_plastic'))//' (each sets the other)', &
        'nu_plastic or foam_alpha, not both')
    call read_pair(rd, io, v, 'curve_strain', 'curve_stress', .true., x, y, n, ok)
    k = 0
    if (ok .and. n > 0) k = findloc([(y(j) > 0.0_wp .and. y(j) >= y(max(j - 1, 1)), j = 1, n)], &
                                    .false., 1)
    if (k > 0) call err_var(rd, io, 'curve_stress', fmt_list(y(1:n)), 'curve_stress('// &
      itoa(k)//') = '//fmt_real(y(k))//' is not > 0, or below the point before')
    ok = ok .and. k == 0
    if (ok .and. n > 0) then
      m%n_curve = n
      m%curve_strain(1:n) = x(1:n)
      m%curve_stress(1:n) = y(1:n)
    end if
    if (n > 0) then                              ! the curve replaces the law
      do k = 1, size(law)
        if (vreal(v, trim(law(k))) /= law_r0(k)) call err_var(rd, io, trim(law(k)), &
          fmt_real(vreal(v, trim(law(k)))), 'has no effect with a curve (curve_strain, '// &
          'curve_stress)', 'not given with curve_strain and curve_stress')
      end do
    else
      if (chk_r(rd, io, v, 'sigma_p', required=.true.)) m%sigma_p = vreal(v, 'sigma_p')
      if (chk_r(rd, io, v, 'eps_d', required=.true.)) m%eps_d = vreal(v, 'eps_d')
    end if
  end subroutine check_foam

  !> &body: the sector (full when not given), the radii and n_circ of a ring (the variables of
  !! the other shapes are warned of by store_rows, from the table's `only`).
  subroutine check_body(rd, io, v, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(inout) :: v
    type(body_cfg_t), intent(inout) :: b
    integer :: parts, n_circ
    if (b%sector_id == 0) then
      b%sector = sector_names(SECTOR_FULL)
      b%sector_id = SECTOR_FULL
    end if
    if (b%shape_id == SHAPE_RING) then
      if (b%r_inner > 0.0_wp .and. b%r_outer > 0.0_wp) then
        if (.not. (b%r_inner < b%r_outer)) call err_var(rd, io, 'r_inner', &
          fmt_real(b%r_inner), 'not below r_outer = '//fmt_real(b%r_outer))
      end if
      n_circ = vint(v, 'n_circ')
      if (n_circ == iunset) n_circ = 0
      parts = 1
      if (b%sector_id == SECTOR_HALF) parts = 2
      if (b%sector_id == SECTOR_QUARTER) parts = 4
      if (n_circ /= 0 .and. n_circ < 3) then
        call err_var(rd, io, 'n_circ', itoa(n_circ), 'out of range')
      else if (mod(n_circ, parts) /= 0) then
        call err_var(rd, io, 'n_circ', itoa(n_circ), 'not divisible by '//itoa(parts)// &
          ' (sector = '''//trim(b%sector)//''')')
      else
        b%n_circ = n_circ
      end if
    end if
    if (b%self_contact .and. b%sector_id == SECTOR_QUARTER) call err_var(rd, io, &
      'self_contact', '.true.', 'not with sector = ''quarter'' (it meets its mirror image on '// &
      'the plane y = centre)')
    if (b%n_thick == iunset) b%n_thick = 16
    select case (b%shape_id)
    case (SHAPE_TUBE)
      call check_tube(rd, io, v, b)
    case (SHAPE_HONEYCOMB)
      call check_honeycomb(rd, io, v, b)
    case (SHAPE_WALLS)
      if (len_trim(b%walls_file) > 0) call read_walls(rd, io, b)
    end select
  end subroutine check_body

  !> A tube: 3 to 64 vertices (pairs, no gaps), a corner radius of 0 or at least t/2.
  subroutine check_tube(rd, io, v, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(in) :: v
    type(body_cfg_t), intent(inout) :: b
    real(wp) :: x(2*max_vertices)
    integer :: n, k
    logical :: ok
    x = v%r(1:2*max_vertices, spec_index_body('vertices'))
    ok = .true.
    call table_count(rd, io, 'vertices', x, n, ok)
    if (.not. ok) return
    if (n == 0) then
      call err_var(rd, io, 'vertices', '', 'missing (required)')
    else if (mod(n, 2) /= 0 .or. n < 6) then
      call err_var(rd, io, 'vertices', fmt_list(x(1:n)), itoa(n)//' numbers: not 3 or more '// &
        'x, y pairs')
    else
      b%n_vertices = n/2
      b%vertices = huge(1.0_wp)
      b%vertices(1:n) = x(1:n)
      do k = 1, b%n_vertices
        if (norm2(x(2*k - 1:2*k) - x(2*modulo(k, b%n_vertices) + 1:2*modulo(k, b%n_vertices) &
            + 2)) <= 0.0_wp) then
          call err_var(rd, io, 'vertices', fmt_list(x(1:n)), 'vertex '//itoa(k)//' repeats '// &
            'the next one')
          return
        end if
      end do
    end if
    if (b%corner_radius > 0.0_wp .and. b%thickness > 0.0_wp .and. &
        b%corner_radius < 0.5_wp*b%thickness) call err_var(rd, io, 'corner_radius', &
      fmt_real(b%corner_radius), 'below thickness/2 = '//fmt_real(0.5_wp*b%thickness)// &
      ' (the inner face would fold)')
  end subroutine check_tube

  !> A honeycomb: whole numbers of cells, an angle that is not 0 and leaves the cells open.
  subroutine check_honeycomb(rd, io, v, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(in) :: v
    type(body_cfg_t), intent(inout) :: b
    real(wp) :: nc(2), open_h
    nc = vvec(v, 'n_cells')
    if (chk_v(rd, io, v, 'n_cells', required=.true.) == 2) then
      if (any(nc /= aint(nc)) .or. any(nc < 1.0_wp) .or. any(nc > real(max_cells, wp))) then
        call err_var(rd, io, 'n_cells', fmt_vec(nc), 'not two whole numbers from 1 to '// &
          itoa(max_cells))
      else
        b%n_cells = nint(nc)
      end if
    end if
    if (abs(b%cell_angle) < 1.0_wp) call err_var(rd, io, 'cell_angle', &
      fmt_real(b%cell_angle), 'too close to 0 (the inclined walls would lie flat)')
    if (b%cell_h > 0.0_wp .and. b%cell_l > 0.0_wp .and. b%thickness > 0.0_wp) then
      open_h = b%cell_h + 2.0_wp*b%cell_l*sin(b%cell_angle*pi/180.0_wp)
      if (open_h <= b%thickness) call err_var(rd, io, 'cell_angle', fmt_real(b%cell_angle), &
        'closes the cells: cell_h + 2 cell_l sin(angle) = '//fmt_real(open_h)// &
        ' m is not above thickness')
    end if
  end subroutine check_honeycomb

  !> The walls CSV (relative to the input's folder): x1, y1, x2, y2, t per line; '#' comments
  !! and a header line of names are skipped. Errors name the file and line.
  subroutine read_walls(rd, io, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(body_cfg_t), intent(inout) :: b
    character(len=:), allocatable :: path, line
    character(len=1024) :: buf, msg
    real(wp) :: r(5)
    real(wp), allocatable :: seg(:,:)
    integer :: u, ios, ln, k
    path = trim(b%walls_file)
    if (path(1:1) /= '/' .and. index(rd%file, '/', back=.true.) > 0) &
      path = rd%file(1:index(rd%file, '/', back=.true.))//path
    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call err_var(rd, io, 'walls_file', ''''//trim(b%walls_file)//'''', 'cannot be read ('// &
        trim(msg)//')')
      return
    end if
    allocate(seg(5, 0))
    ln = 0
    do
      read(u, '(a)', iostat=ios) buf
      if (ios /= 0) exit
      ln = ln + 1
      line = trim(adjustl(buf))
      if (len(line) == 0) cycle
      if (line(1:1) == '#') cycle
      if (ln == 1 .and. verify(line(1:1), '0123456789+-.') /= 0) cycle    ! a header
      read(line, *, iostat=ios) r
      if (ios /= 0 .or. .not. all(abs(r) <= huge(1.0_wp))) then
        call err_var(rd, io, 'walls_file', ''''//trim(b%walls_file)//'''', path//':'// &
          itoa(ln)//': '''//line//''' is not 5 finite numbers x1, y1, x2, y2, thickness')
        close(u)
        return
      end if
      if (r(5) <= 0.0_wp .or. norm2(r(3:4) - r(1:2)) <= 0.0_wp) then
        call err_var(rd, io, 'walls_file', ''''//trim(b%walls_file)//'''', path//':'// &
          itoa(ln)//': a wall of zero length or thickness')
        close(u)
        return
      end if
      if (size(seg, 2) >= 4096) then
        call err_var(rd, io, 'walls_file', ''''//trim(b%walls_file)//'''', 'more than 4096 walls')
        close(u)
        return
      end if
      seg = reshape([seg, r], [5, size(seg, 2) + 1])
    end do
    close(u)
    if (size(seg, 2) == 0) then
      call err_var(rd, io, 'walls_file', ''''//trim(b%walls_file)//'''', 'has no walls')
      return
    end if
    k = size(seg, 2)
    call move_alloc(seg, b%seg)
  end subroutine read_walls

  !> The particles of a tube, honeycomb, walls or disc can be made (mpm_sections' reasons).
  subroutine check_mesh(rd, io, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(body_cfg_t), intent(in) :: b
    real(wp), allocatable :: xc(:,:)
    integer, allocatable :: quad(:,:), pwall(:)
    integer :: stat
    character(len=:), allocatable :: msg
    real(wp) :: np, nc, ext
    real(wp), parameter :: mesh_check_max = 2.0e7_wp  ! particles the check meshes at most
    if (b%shape_id == SHAPE_TUBE .and. (b%n_vertices < 3 .or. b%thickness <= 0.0_wp)) return
    if (b%shape_id == SHAPE_HONEYCOMB .and. (any(b%n_cells < 1) .or. b%thickness <= 0.0_wp &
        .or. b%cell_l <= 0.0_wp .or. b%cell_h <= 0.0_wp)) return
    if (b%shape_id == SHAPE_WALLS .and. .not. allocated(b%seg)) return
    if (b%shape_id == SHAPE_DISC .and. b%r_outer <= 0.0_wp) return
    call body_estimate(b, np, nc, ext)     ! lengths in a wrong unit: refused later, unmeshed
    if (np > mesh_check_max) return
    call body_mesh(b, xc, quad, pwall, stat, msg)
    if (stat == 2) call err_var(rd, io, 'sector', ''''//trim(b%sector)//'''', msg// &
      ' through center = '//fmt_vec(b%center), '''full'', or a section that is its own mirror'// &
      ' image about the planes x = center(1) (and y = center(2) for a quarter), every wall'// &
      ' that reaches them square to them')
    if (stat == 3 .and. b%shape_id == SHAPE_TUBE) call err_var(rd, io, 'vertices', &
      fmt_list(b%vertices(1:2*b%n_vertices)), 'the polygon crosses itself: '//msg, &
      'a simple polygon, counter-clockwise')
    if (stat == 3 .and. b%shape_id /= SHAPE_TUBE) call err_var(rd, io, 'walls_file', &
      ''''//trim(b%walls_file)//'''', msg, 'walls that meet only at their ends')
    if (stat == 1) call err_var(rd, io, 'n_thick', itoa(b%n_thick), &
      'the walls cannot be '// &
      'filled with particles: '//msg, 'walls longer than their joints need, meeting at '// &
      'angles they can (n_thick even where three or more walls meet)')
  end subroutine check_mesh

  pure integer function spec_index_body(name) result(r)
    character(len=*), intent(in) :: name
    r = spec_index('body', name)
  end function spec_index_body

  !> &wall: a unit normal, friction only with Coulomb contact, the motion table.
  subroutine check_wall(rd, io, v, w)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(inout) :: v
    type(wall_cfg_t), intent(inout) :: w
    real(wp) :: normal(2), length
    normal = vvec(v, 'normal')
    if (chk_v(rd, io, v, 'normal') == 2) then
      length = sqrt(normal(1)**2 + normal(2)**2)
      if (length == 0.0_wp) then
        call err_var(rd, io, 'normal', fmt_vec(normal), 'zero vector')
      else if (abs(length - 1.0_wp) > 1.0e-6_wp) then
        call err_var(rd, io, 'normal', fmt_vec(normal), 'not of unit length (|normal| = '// &
          fmt_short(length)//'); use normal = '//fmt_vec(normal/length))
      else
        w%normal = normal
      end if
    end if
    call check_friction(rd, io, 'contact', w%contact, w%contact_id, w%friction)
    call read_motion(rd, io, v, w)
    call check_free_wall(rd, io, w)
  end subroutine check_wall

  !> A wall with mass moves freely along its normal: no prescribed law (ramp, table, stroke),
  !! not a mirror plane, and its initial velocity along the normal. A stroke needs a motion.
  subroutine check_free_wall(rd, io, w)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(wall_cfg_t), intent(inout) :: w
    real(wp) :: vt(2)
    character(len=*), parameter :: free = 'only with mass = 0 (a wall with mass moves freely '// &
      'under the material''s reaction and gravity)'
    if (w%stroke > 0.0_wp .and. all(w%velocity == 0.0_wp) .and. .not. w%mass > 0.0_wp) &
      call err_var(rd, io, 'stroke', fmt_real(w%stroke), 'given for a wall that does not '// &
        'move (velocity = 0, 0)', 'stroke > 0 with a velocity, or stroke = 0')
    if (.not. w%mass > 0.0_wp) return
    if (w%contact_id == CONTACT_SLIP) call err_var(rd, io, 'mass', fmt_real(w%mass), &
      'given for a ''slip'' mirror plane', 'mass = 0 with contact = ''slip''')
    if (w%contact_id == CONTACT_BONDED) call err_var(rd, io, 'mass', fmt_real(w%mass), &
      'given for a ''bonded'' wall (a free body strikes the material and rebounds; a tie '// &
      'would hold it)', 'mass = 0 with contact = ''bonded'', or contact = ''coulomb'' '// &
      'or ''stick'' with mass > 0')
    if (w%stroke > 0.0_wp) call err_var(rd, io, 'stroke', fmt_real(w%stroke), &
      'given with mass = '//fmt_real(w%mass), free)
    if (w%ramp > 0.0_wp) call err_var(rd, io, 'ramp', fmt_real(w%ramp), &
      'given with mass = '//fmt_real(w%mass), free)
    if (w%n_motion > 0) call err_var(rd, io, 'motion_t', fmt_list(w%motion_t(1:w%n_motion)), &
      'given with mass = '//fmt_real(w%mass), free)
    vt = w%velocity - dot_product(w%velocity, w%normal)*w%normal
    if (norm2(vt) > 1.0e-9_wp*max(norm2(w%velocity), tiny(1.0_wp))) call err_var(rd, io, &
      'velocity', fmt_vec(w%velocity), 'has a part along the wall ('//fmt_vec(vt)// &
      ' m/s): a wall with mass moves along its normal only', 'a multiple of normal = '// &
      fmt_vec(w%normal))
  end subroutine check_free_wall

  !> Friction > 0 only with the Coulomb law or 'bonded' (for what is not tied; else reported,
  !! and left at 0).
  subroutine check_friction(rd, io, var, law, id, friction)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, id
    character(len=*), intent(in) :: var, law     !! the law's variable and its value
    real(wp), intent(inout) :: friction
    if (friction > 0.0_wp .and. id > 0 .and. id /= CONTACT_COULOMB .and. &
        id /= CONTACT_BONDED) then
      if (var == 'contact') then           ! &wall
        call err_var(rd, io, 'friction', fmt_real(friction), 'has no effect with '//var// &
          ' = '''//trim(law)//'''; set '//var//' = ''coulomb'' or ''bonded'', or friction = 0')
      else
        call err_var(rd, io, 'friction', fmt_real(friction), 'has no effect with '//var// &
          ' = '''//trim(law)//'''; set '//var//' = ''coulomb'' or friction = 0')
      end if
      friction = 0.0_wp
    end if
  end subroutine check_friction

  !> The motion table of a wall (read_pair).
  subroutine read_motion(rd, io, v, w)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(in) :: v
    type(wall_cfg_t), intent(inout) :: w
    real(wp) :: motion_t(max_table), motion_f(max_table)
    integer :: nt
    logical :: table_ok
    call read_pair(rd, io, v, 'motion_t', 'motion_f', .false., motion_t, motion_f, nt, table_ok)
    if (table_ok) then
      w%n_motion = nt
      w%motion_t(1:nt) = motion_t(1:nt)
      w%motion_f(1:nt) = motion_f(1:nt)
      if (nt > 0 .and. w%ramp > 0.0_wp) call warn_var(rd, io, 'ramp', &
        'ignored: the motion table replaces it')
    end if
  end subroutine read_motion

  !> A table of two rows xn, yn (a wall's motion, a foam's curve): the entries given are the
  !! leading non-sentinel ones, as many in each; x(1) >= 0 (0 with first_zero), x strictly
  !! increasing. ok: no problem found (n is the count given).
  subroutine read_pair(rd, io, v, xn, yn, first_zero, x, y, n, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(in) :: v
    character(len=*), intent(in) :: xn, yn       !! the names of the rows
    logical, intent(in) :: first_zero            !! x(1) must be 0
    real(wp), intent(out) :: x(max_table), y(max_table)
    integer, intent(out) :: n
    logical, intent(out) :: ok
    integer :: ny, k
    x = vtab(v, xn)
    y = vtab(v, yn)
    ok = .true.
    call table_count(rd, io, xn, x, n, ok)
    call table_count(rd, io, yn, y, ny, ok)
    if (ok .and. n /= ny) then
      call err_var(rd, io, yn, fmt_list(y(1:ny)), itoa(ny)//' values but '//xn//' has '//itoa(n))
      ok = .false.
    end if
    if (ok .and. n > 0) then
      if (x(1) < 0.0_wp .or. (first_zero .and. x(1) /= 0.0_wp)) then
        call err_var(rd, io, xn, fmt_list(x(1:n)), xn//'(1) = '//fmt_real(x(1))// &
          trim(merge(' is not 0   ', ' is negative', first_zero .and. x(1) > 0.0_wp)))
        ok = .false.
      end if
    end if
    do k = 2, n
      if (.not. ok) exit
      if (.not. (x(k) > x(k-1))) then
        call err_var(rd, io, xn, fmt_list(x(1:n)), 'not strictly increasing: '//xn//'('// &
          itoa(k)//') = '//fmt_real(x(k))//' <= '//xn//'('//itoa(k-1)//') = '//fmt_real(x(k-1)))
        ok = .false.
      end if
    end do
  end subroutine read_pair

  !> &contact: two different bodies, or 0, 0 (checked against the &body groups in
  !! mpm_config_check: they may come later in the file), friction only with Coulomb.
  subroutine check_contact(rd, io, v, c)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(values_t), intent(inout) :: v
    type(contact_cfg_t), intent(inout) :: c
    real(wp) :: b(2)
    b = vvec(v, 'bodies')
    if (chk_v(rd, io, v, 'bodies') == 2) then
      if (any(b < 0.0_wp) .or. any(b /= aint(b)) .or. any(b > 1.0e6_wp)) then
        call err_var(rd, io, 'bodies', fmt_vec(b), 'not two whole numbers from 0 to 1000000')
      else if (count(b == 0.0_wp) == 1) then
        call err_var(rd, io, 'bodies', itoa(nint(b(1)))//', '//itoa(nint(b(2))), 'one body '// &
          'given with 0 (0, 0 stands for every pair not named elsewhere)')
      else if (b(1) == b(2) .and. b(1) > 0.0_wp) then
        call err_var(rd, io, 'bodies', itoa(nint(b(1)))//', '//itoa(nint(b(2))), 'a body '// &
          'cannot be in contact with itself')
      else
        c%bodies = nint(b)
      end if
    end if
    call check_friction(rd, io, 'law', c%law, c%law_id, c%friction)
  end subroutine check_contact

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
