!> The one validator of the input, after the generic checks of each variable against its row
!! (mpm_config): the rules that tie the variables of a group together, and those across groups
!! (defaults that depend on other groups, references, bounds, the fixed time step, the mirror
!! planes, the bodies' placement, values in a likely wrong unit). Every violation is reported,
!! one message each, with its file:line, group, variable, value and what is allowed.
! SPDX-License-Identifier: MIT
module mpm_config_check
  use mpm_kinds, only: wp
  use mpm_constants, only: SHAPE_DISC, BASIS_CPDI2, SCHEME_MUSL, PLANE_STRAIN, SHAPE_RING, &
                           VOLUMETRIC_FBAR, VOLUMETRIC_FBARWALL, PLANE_STRESS, MODEL_NEOHOOKEAN, &
                           MODEL_J2, MODEL_FOAM, RATE_COWPER_SYMONDS, FLOW_JOHNSON_COOK, &
                           CONTACT_COULOMB, CONTACT_SLIP, CONTACT_BONDED, SHAPE_TUBE, &
                           SHAPE_FILLER, shape_names, max_table
  use mpm_config_types, only: config_t, grid_cfg_t, material_cfg_t, wall_cfg_t, contact_cfg_t, &
                              unset_real, stiffest_penalty
  use mpm_bodies, only: body_box, body_mesh
  use mpm_config_text, only: lower, itoa, quote, fmt_short, fmt_list, fmt_real, &
                             finite
  use mpm_config_table, only: n_groups
  use mpm_config_scan, only: reader_t, occurrence, err_var, err_missing, warn_group, &
                             given
  use mpm_walls, only: wall_t, wall_stroke_setup, wall_end_time, wall_stroke_travel
  use mpm_units, only: advice_unit_issues, unit_issue_t
  use mpm_symmetry, only: symmetry_checks
  use mpm_config_body, only: check_body, table_count
  use mpm_placement, only: placement_checks
  use mpm_material, only: material_from, material_wave_speed
  use mpm_time_step, only: time_step_dt, cfl_margin, cfl_tried_min
  implicit none
  private
  public :: check_group, cross_checks, unit_checks

contains

  !> The rules of occurrence io, the k-th of group ig, on its record in cfg.
  subroutine check_group(rd, io, ig, k, cfg)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, ig, k
    type(config_t), intent(inout) :: cfg
    select case (ig)
    case (3); call check_grid(rd, io, cfg%grid)
    case (4); call check_material(rd, io, cfg%materials(k))
    case (5); call check_body(rd, io, cfg%bodies(k))
    case (6); call check_wall(rd, io, cfg%walls(k))
    case (8); call check_contact(rd, io, cfg%contacts(k))
    end select
  end subroutine check_group

  ! ------------------------------------------------------------ the rules of the groups

  !> &grid: lower and upper, both or neither.
  subroutine check_grid(rd, io, g)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(grid_cfg_t), intent(inout) :: g
    logical :: nl, nu
    nl = given(rd, io, 'lower') .and. all(finite(g%lower))
    nu = given(rd, io, 'upper') .and. all(finite(g%upper))
    g%fitted = .not. (nl .and. nu)
    if (nl .and. nu) then
      if (.not. all(g%lower < g%upper)) call err_var(rd, io, 'upper', fmt_list(g%upper), &
        'not above lower = '//fmt_list(g%lower)//' in both components')
    else if (nl .and. .not. given(rd, io, 'upper')) then
      call err_var(rd, io, 'lower', fmt_list(g%lower), 'given without upper')
    else if (nu .and. .not. given(rd, io, 'lower')) then
      call err_var(rd, io, 'upper', fmt_list(g%upper), 'given without lower')
    end if
    if (g%fitted) g%lower = 0.0_wp
    if (g%fitted) g%upper = 0.0_wp
  end subroutine check_grid

  !> &material: sigma_y (required for j2), the variables a model does not use, and the flow
  !! stress law: with Johnson-Cook (A is sigma_y) the linear law's own variables (hardening,
  !! rate_law) must be left at their defaults; the foam's variables (check_foam).
  subroutine check_material(rd, io, m)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(material_cfg_t), intent(inout) :: m
    character(len=*), parameter :: jc = 'flow_stress = ''johnson_cook'''
    character(len=:), allocatable :: not_j2
    not_j2 = 'not used by model = '''//trim(m%model)//''''
    if (m%model_id == MODEL_J2 .and. .not. given(rd, io, 'sigma_y')) &
      call err_missing(rd, io, 'sigma_y')
    if (m%model_id /= MODEL_J2 .and. m%model_id > 0 .and. given(rd, io, 'sigma_y')) &
      call err_var(rd, io, 'sigma_y', '', not_j2//'. Delete it', warn=.true.)
    if (m%rate_law_id == RATE_COWPER_SYMONDS .and. m%model_id /= MODEL_J2) call warn_group(rd, &
      io, 'rate_law needs model = ''j2''. Set rate_law = ''none''')
    if (m%flow_stress_id == FLOW_JOHNSON_COOK) then
      if (m%model_id /= MODEL_J2 .and. m%model_id > 0) call warn_group(rd, io, 'flow_stress '// &
        'needs model = ''j2''. Set flow_stress = ''linear''')
      if (m%hardening > 0.0_wp) call err_var(rd, io, 'hardening', fmt_real(m%hardening), &
        'has no effect with '//jc//' (jc_b and jc_n give its hardening)', &
        '0 with '//jc//' (or flow_stress = ''linear'')')
      if (m%voce_q > 0.0_wp) call err_var(rd, io, 'voce_q', fmt_real(m%voce_q), &
        'has no effect with '//jc, '0 with '//jc//' (or flow_stress = ''linear'')')
      if (m%rate_law_id == RATE_COWPER_SYMONDS) call err_var(rd, io, 'rate_law', &
        '''cowper_symonds''', 'cannot be combined with '//jc//' (jc_c and jc_rate0 give '// &
        'its rate effect)', '''none'' with '//jc//' (or flow_stress = ''linear'')')
    else if (m%jc_b /= 0.0_wp .or. m%jc_n /= 1.0_wp .or. m%jc_c /= 0.0_wp .or. &
             m%jc_rate0 /= 1.0_wp) then
      call warn_group(rd, io, 'jc_* need flow_stress = ''johnson_cook''. Delete them')
    end if
    if (m%model_id == MODEL_FOAM) call check_foam(rd, io, m)
    m%curve_strain(m%n_curve+1:) = 0.0_wp      ! past the curve: the type's default
    m%curve_stress(m%n_curve+1:) = 0.0_wp
  end subroutine check_material

  !> &material, model = 'foam': nu_plastic or foam_alpha, not both; the hardening law
  !! (sigma_p and eps_d required) or the tabulated curve (then none of the law's variables).
  subroutine check_foam(rd, io, m)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(material_cfg_t), intent(inout) :: m
    character(len=*), parameter :: law(5) = [character(len=11) :: 'sigma_p', 'eps_d', &
      'foam_gamma', 'foam_alpha2', 'foam_beta']
    integer :: n, k, j
    logical :: ok
    if (given(rd, io, 'nu_plastic') .and. given(rd, io, 'foam_alpha')) call err_var(rd, io, &
      'foam_alpha', fmt_real(m%foam_alpha), 'given with nu_plastic = '// &
      fmt_real(m%nu_plastic)//' (each sets the other)', 'nu_plastic or foam_alpha, not both')
    call read_pair(rd, io, 'curve_strain', 'curve_stress', .true., m%curve_strain, &
                   m%curve_stress, n, ok)
    k = 0
    if (ok .and. n > 0) k = findloc([(m%curve_stress(j) > 0.0_wp .and. m%curve_stress(j) >= &
      m%curve_stress(max(j - 1, 1)), j = 1, n)], .false., 1)
    if (k > 0) call err_var(rd, io, 'curve_stress', fmt_list(m%curve_stress(1:n)), &
      'curve_stress('//itoa(k)//') = '//fmt_real(m%curve_stress(k))//' is not > 0, or '// &
      'below the point before')
    if (ok .and. n > 1 .and. k == 0) k = findloc([(m%curve_strain(j) - m%curve_strain(j - 1) &
      >= 1.0e-9_wp, j = 2, n)], .false., 1)
    if (k > 0 .and. ok) then                     ! (finer steps: slopes beyond the program's)
      call err_var(rd, io, 'curve_strain', fmt_list(m%curve_strain(1:n)), 'curve_strain('// &
        itoa(k + 1)//') is less than 1e-9 above the point before')
      ok = .false.
    end if
    if (ok .and. k == 0) m%n_curve = n
    do k = 1, size(law)                          ! the curve replaces the law
      if (n > 0 .and. given(rd, io, trim(law(k)))) call err_var(rd, io, trim(law(k)), '', &
        'has no effect with a curve (curve_strain, curve_stress)', &
        'not given with curve_strain and curve_stress')
      if (n == 0 .and. k <= 2 .and. .not. given(rd, io, trim(law(k)))) &
        call err_missing(rd, io, trim(law(k)))
    end do
  end subroutine check_foam


  !> &wall: a unit normal, friction only with Coulomb contact, the motion table.
  subroutine check_wall(rd, io, w)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(wall_cfg_t), intent(inout) :: w
    real(wp) :: length
    integer :: nt
    logical :: ok
    if (given(rd, io, 'normal') .and. all(finite(w%normal))) then
      length = sqrt(w%normal(1)**2 + w%normal(2)**2)
      if (length == 0.0_wp) then
        call err_var(rd, io, 'normal', fmt_list(w%normal), 'zero vector')
      else if (abs(length - 1.0_wp) > 1.0e-6_wp) then
        call err_var(rd, io, 'normal', fmt_list(w%normal), 'not of unit length (|normal| = '// &
          fmt_short(length)//'); use normal = '//fmt_list(w%normal/length))
      end if
    end if
    call check_friction(rd, io, 'contact', w%contact, w%contact_id, w%friction)
    if (w%contact_id == CONTACT_SLIP .and. w%penalty /= 1.0_wp) call err_var(rd, io, &
      'penalty', fmt_real(w%penalty), 'has no effect with contact = ''slip'' (a mirror plane '// &
      'has no penalty)', '1 with contact = ''slip''')
    ! (its factors, as every number without a unit, are at most vmax in size: mpm_config_table)
    call read_pair(rd, io, 'motion_t', 'motion_f', .false., w%motion_t, w%motion_f, nt, ok)
    if (ok) w%n_motion = nt
    if (ok .and. nt > 0 .and. w%ramp > 0.0_wp) call err_var(rd, io, 'ramp', '', &
      'the motion table replaces it. Set ramp = 0', warn=.true.)
    w%motion_t(w%n_motion+1:) = 0.0_wp         ! past the table: the type's default
    w%motion_f(w%n_motion+1:) = 0.0_wp
    call check_free_wall(rd, io, w)
  end subroutine check_wall

  !> A wall with mass moves freely along its normal: no prescribed law (ramp, table, stroke),
  !! not a mirror plane, and its initial velocity along the normal. A stroke needs a motion.
  subroutine check_free_wall(rd, io, w)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(wall_cfg_t), intent(inout) :: w
    real(wp) :: vt(2)
    character(len=:), allocatable :: with_mass
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
    with_mass = 'given with mass = '//fmt_real(w%mass)
    if (w%stroke > 0.0_wp) call err_var(rd, io, 'stroke', fmt_real(w%stroke), with_mass, free)
    if (w%ramp > 0.0_wp) call err_var(rd, io, 'ramp', fmt_real(w%ramp), with_mass, free)
    if (w%n_motion > 0) call err_var(rd, io, 'motion_t', fmt_list(w%motion_t(1:w%n_motion)), &
      with_mass, free)
    vt = w%velocity - dot_product(w%velocity, w%normal)*w%normal
    if (norm2(vt) > 1.0e-9_wp*max(norm2(w%velocity), tiny(1.0_wp))) call err_var(rd, io, &
      'velocity', fmt_list(w%velocity), 'has a part along the wall ('//fmt_list(vt)// &
      ' m/s): a wall with mass moves along its normal only', 'a multiple of normal = '// &
      fmt_list(w%normal))
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
      call err_var(rd, io, 'friction', fmt_real(friction), 'has no effect with '//var// &
        ' = '''//trim(law)//'''; set '//var//' = ''coulomb'' or ''bonded'', or friction = 0')
      friction = 0.0_wp
    end if
  end subroutine check_friction

  !> A table of two rows xn, yn (a wall's motion, a foam's curve): the entries given are the
  !! leading non-sentinel ones, as many in each; x(1) >= 0 (0 with first_zero), x strictly
  !! increasing. ok: no problem found (n is the count given; else x and y are reset).
  subroutine read_pair(rd, io, xn, yn, first_zero, x, y, n, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: xn, yn       !! the names of the rows
    logical, intent(in) :: first_zero            !! x(1) must be 0
    real(wp), intent(inout) :: x(max_table), y(max_table)  !! as read (unset_real: not given)
    integer, intent(out) :: n
    logical, intent(out) :: ok
    integer :: ny, k
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
    if (ok) return
    x = unset_real
    y = unset_real
  end subroutine read_pair


  !> &contact: two different bodies, or 0, 0 (checked against the &body groups in
  !! mpm_config_check: they may come later in the file), friction only with Coulomb.
  subroutine check_contact(rd, io, c)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(contact_cfg_t), intent(inout) :: c
    integer :: b(2)
    b = c%bodies
    if (count(b == 0) == 1) then
      call err_var(rd, io, 'bodies', '', 'one body given with 0 (0, 0 stands for every pair '// &
        'not named elsewhere)')
    else if (b(1) == b(2) .and. b(1) > 0) then
      call err_var(rd, io, 'bodies', '', 'a body cannot be in contact with itself')
    end if
    if (c%law_id == 4) c%law_id = CONTACT_BONDED   ! the list's 4th name (enum_names)
    call check_friction(rd, io, 'law', c%law, c%law_id, c%friction)
  end subroutine check_contact

  !> Defaults that depend on other groups, references, bounds, the fixed time step.
  subroutine cross_checks(rd, cfg, first_of, occ_mat, occ_body, occ_con)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(inout) :: cfg
    integer, intent(in) :: first_of(n_groups), occ_mat(:), occ_body(:), occ_con(:)
    integer :: k, j, id, io_run, io_solver, io_grid, n0
    logical :: all_named, all_ok, fbar
    character(len=:), allocatable :: names_txt, want, vname

    io_run = first_of(1)
    io_solver = first_of(2)
    io_grid = first_of(3)
    if (len_trim(cfg%run%title) == 0) then      ! the file name without folder and extension
      cfg%run%title = rd%file(index(rd%file, '/', back=.true.) + 1:)
      j = index(cfg%run%title, '.', back=.true.)
      if (j > 1) cfg%run%title(j:) = ''
      if (len_trim(cfg%run%title) == 0) cfg%run%title = 'case'
    end if
    if (len_trim(cfg%run%output_dir) == 0) cfg%run%output_dir = 'out/'//trim(cfg%run%title)
    if (io_solver == 0) then
      cfg%solver%basis_id = BASIS_CPDI2
      cfg%solver%scheme_id = SCHEME_MUSL
      cfg%solver%plane_id = PLANE_STRAIN
    end if

    ! material names: given and unique (case-insensitive)
    all_named = .true.
    names_txt = ''
    do k = 1, size(cfg%materials)
      if (.not. rd%occ(occ_mat(k))%read_ok .or. len_trim(cfg%materials(k)%name) == 0) then
        all_named = .false.
        cycle
      end if
      if (len(names_txt) > 0) names_txt = names_txt//', '
      names_txt = names_txt//quote(trim(cfg%materials(k)%name))
      j = findloc(lower(cfg%materials(1:k-1)%name), lower(cfg%materials(k)%name), 1)
      if (j > 0) call err_var(rd, occ_mat(k), 'name', quote(trim(cfg%materials(k)%name)), &
        'already used by &material #'//itoa(j)//' (line '//itoa(rd%occ(occ_mat(j))%line)// &
        ')', 'a name that no other &material uses')
    end do

    ! 'fbar', 'fbarwall' (mpm_fbar): the rate models elastic and j2, plane strain; 'fbarwall': rings
    fbar = io_solver > 0 .and. cfg%solver%volumetric_id >= VOLUMETRIC_FBAR
    vname = ''''//trim(cfg%solver%volumetric)//''''
    if (fbar .and. (cfg%solver%plane_id == PLANE_STRESS .or. any(cfg%materials%model_id == &
        MODEL_NEOHOOKEAN))) call err_var(rd, io_solver, 'volumetric', vname, 'needs plane = '// &
      '''strain'' and no &material of model = ''neohookean''', '''standard'', or ''fbar'' or '// &
      '''fbarwall'' with plane = ''strain'' and the models ''elastic'', ''j2'', ''foam''')
    if (fbar .and. (size(cfg%bodies) > 1 .or. any(cfg%bodies%self_contact))) call err_var(rd, &
      io_solver, 'volumetric', vname, 'averages the volume change within one velocity field; '// &
      'here are '//itoa(size(cfg%bodies) + count(cfg%bodies%self_contact))//' (one per body, '// &
      'two with self_contact)', '''standard'' with several bodies or self_contact, or one &body')
    if (fbar .and. cfg%solver%volumetric_id == VOLUMETRIC_FBARWALL .and. any(cfg%bodies% &
        shape_id /= SHAPE_RING)) call err_var(rd, io_solver, 'volumetric', vname, 'needs rings '// &
      '(it fits through a ring''s wall)', '''standard'' or ''fbar'', or shape = ''ring''')
    if (fbar .and. any(cfg%bodies%shape_id == SHAPE_DISC)) call err_var(rd, io_solver, &
      'volumetric', vname, 'is not for a solid disc (it loses 2-3 % of the energy at a wall '// &
      'there)', '''standard'' with a &body of shape ''disc''')
    ! body -> material
    do k = 1, size(cfg%bodies)
      if (.not. rd%occ(occ_body(k))%read_ok .or. size(cfg%materials) == 0) cycle
      want = trim(cfg%bodies(k)%material)
      if (len(want) == 0) then
        cfg%bodies(k)%material_id = 1
        cfg%bodies(k)%material = cfg%materials(1)%name
        cycle
      end if
      id = findloc(lower(cfg%materials%name), lower(want), 1)
      if (id > 0) then
        cfg%bodies(k)%material_id = id
        cfg%bodies(k)%material = cfg%materials(id)%name
      else if (all_named) then
        call err_var(rd, occ_body(k), 'material', quote(want), 'no &material has this name', &
          'the name of a &material: '//names_txt//' (or not given: the first material)')
      end if
    end do

    call filler_checks(rd, cfg, occ_body)          ! fillers take their tubes' geometry
    call bonded_checks(rd, cfg, occ_con)
    ! strokes reached, and t_end from them where it is not given
    if (io_run > 0) call stroke_checks(rd, cfg, io_run)

    ! given grid bounds contain every body
    if (io_grid > 0) call grid_bounds_checks(rd, cfg, io_grid, occ_body)

    ! a fixed time step must not exceed the stable limit at cfl = 1
    all_ok = io_run > 0 .and. io_grid > 0 .and. size(cfg%materials) > 0 .and. &
             size(cfg%bodies) > 0
    if (all_ok) all_ok = rd%occ(io_run)%ok .and. rd%occ(io_grid)%ok .and. &
                         all(rd%occ(occ_mat)%ok) .and. all(rd%occ(occ_body)%ok)
    if (all_ok .and. io_solver > 0) all_ok = rd%occ(io_solver)%ok
    if (all_ok) call check_time_step(rd, cfg, io_run)

    ! a half or quarter model: nothing may move across its mirror planes (mpm_symmetry)
    call symmetry_checks(rd, cfg)
    n0 = rd%n_err
    if (cfg%run%check_units) call unit_checks(rd, cfg)
    if (io_grid > 0 .and. rd%n_err == n0) then   ! bodies apart, in front of the walls
      if (rd%occ(io_grid)%ok) call placement_checks(rd, cfg, occ_body)
    end if

    call contact_checks(rd, cfg, occ_con)
  end subroutine cross_checks

  !> A filler (shape = 'filler') fills a 'tube' given before it (`fills`): the tube's
  !! centreline, thickness, corner radius, n_thick, centre and sector become the filler's (its
  !! own centre, if given, must be the tube's), then its particles must be possible
  !! (mpm_filler's filler_mesh: a convex inner face, a gap that closes none of its edges).
  subroutine filler_checks(rd, cfg, occ_body)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(inout) :: cfg
    integer, intent(in) :: occ_body(:)
    character(len=*), parameter :: a_tube = 'the number of a &body of shape ''tube'' given '// &
      'before this one'
    integer :: k, j, io, stat
    real(wp), allocatable :: xc(:,:)
    integer, allocatable :: quad(:,:), pwall(:)
    character(len=:), allocatable :: msg
    do k = 1, size(cfg%bodies)
      io = occ_body(k)
      if (.not. rd%occ(io)%ok .or. cfg%bodies(k)%shape_id /= SHAPE_FILLER) cycle
      associate (b => cfg%bodies(k))
        j = b%fills
        if (j < 1 .or. j >= k) then
          call err_var(rd, io, 'fills', itoa(j), 'not a &body given before this one (this '// &
            'is &body #'//itoa(k)//')', a_tube)
          cycle
        end if
        if (.not. rd%occ(occ_body(j))%ok) cycle      ! (its own errors are reported)
        if (cfg%bodies(j)%shape_id /= SHAPE_TUBE) then
          call err_var(rd, io, 'fills', itoa(j), '&body #'//itoa(j)//' is a '''// &
            trim(shape_names(cfg%bodies(j)%shape_id))//''', not a ''tube''', a_tube)
          cycle
        end if
        if (any(b%center /= 0.0_wp) .and. any(b%center /= cfg%bodies(j)%center)) then
          call err_var(rd, io, 'center', fmt_list(b%center), 'not the centre of the tube it '// &
            'fills, &body #'//itoa(j)//' ('//fmt_list(cfg%bodies(j)%center)//')', &
            'not given (a filler takes its tube''s), or the tube''s')
          cycle
        end if
        b%center = cfg%bodies(j)%center
        b%sector = cfg%bodies(j)%sector
        b%sector_id = cfg%bodies(j)%sector_id
        b%vertices = cfg%bodies(j)%vertices
        b%n_vertices = cfg%bodies(j)%n_vertices
        b%thickness = cfg%bodies(j)%thickness
        b%corner_radius = cfg%bodies(j)%corner_radius
        b%host_n_thick = cfg%bodies(j)%n_thick
        call body_mesh(b, xc, quad, pwall, stat, msg)
        if (stat == 0) cycle
        if (index(msg, 'fill_gap') > 0) then
          call err_var(rd, io, 'fill_gap', fmt_real(b%fill_gap), msg, 'a gap >= 0 that '// &
            'closes no edge of the inner face')
        else
          call err_var(rd, io, 'fills', itoa(j), 'the tube cannot be filled: '//msg, &
            'a &body of shape ''tube'' whose inner face is convex')
        end if
      end associate
    end do
  end subroutine filler_checks

  !> law = 'bonded' between bodies needs basis 'cpdi2': the ties join the shared domain
  !! corners of the two surfaces (mpm_body_tie).
  subroutine bonded_checks(rd, cfg, occ_con)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: occ_con(:)
    integer :: k
    do k = 1, size(cfg%contacts)
      if (.not. rd%occ(occ_con(k))%ok) cycle
      if (cfg%contacts(k)%law_id == CONTACT_BONDED .and. cfg%solver%basis_id /= BASIS_CPDI2 &
          .and. cfg%solver%basis_id > 0) call err_var(rd, occ_con(k), 'law', '''bonded''', &
        'ties the shared domain corners of the two surfaces, which only &solver basis = '// &
        '''cpdi2'' has (basis = '''//trim(cfg%solver%basis)//''')', '''frictionless'', '// &
        '''coulomb'' or ''stick'', or basis = ''cpdi2''')
    end do
  end subroutine bonded_checks

  !> Every stroke is reached by its wall's motion law; without t_end, the run ends when every
  !! moving wall has reached its stroke (t_end is required when one has none, or with a wall of
  !! mass).
  subroutine stroke_checks(rd, cfg, io_run)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(inout) :: cfg
    integer, intent(in) :: io_run
    type(wall_t) :: w
    integer :: k, io
    logical :: ok, all_stroke, any_moving, any_mass
    real(wp) :: t_stop, travel
    character(len=:), allocatable :: without, rest
    all_stroke = .true.
    any_moving = .false.
    any_mass = .false.
    t_stop = 0.0_wp
    without = ''
    rest = ''                 ! (gfortran -O2 would warn it may be used uninitialized)
    do k = 1, size(cfg%walls)
      if (cfg%walls(k)%mirror) cycle
      io = occurrence(rd, 'wall', k)
      if (io > 0) then
        if (.not. rd%occ(io)%ok) cycle
      end if
      if (cfg%walls(k)%mass > 0.0_wp) then
        any_mass = .true.
        cycle
      end if
      if (all(cfg%walls(k)%velocity == 0.0_wp)) cycle
      any_moving = .true.
      w%velocity = cfg%walls(k)%velocity
      w%normal = cfg%walls(k)%normal
      w%ramp = cfg%walls(k)%ramp
      w%n_motion = cfg%walls(k)%n_motion
      w%motion_t = cfg%walls(k)%motion_t
      w%motion_f = cfg%walls(k)%motion_f
      w%stroke = cfg%walls(k)%stroke
      call wall_stroke_setup(w, ok)
      if (.not. ok .and. io > 0) then
        travel = wall_stroke_travel(w, huge(1.0_wp)*1.0e-10_wp)    ! (at rest, or moving away)
        if (travel < 0.0_wp) then
          rest = 'the motion table ends moving the wall away from the material'
        else
          rest = 'the motion comes to rest after '//fmt_short(travel)//' m'
        end if
        call err_var(rd, io, 'stroke', fmt_real(w%stroke), 'not reached: '//rest, &
          'a stroke the motion reaches, or a motion table that keeps moving')
        all_stroke = .false.
      else if (w%stroke > 0.0_wp) then
        t_stop = max(t_stop, wall_end_time(w))
      else
        all_stroke = .false.
        if (len(without) > 0) without = without//', '
        without = without//'#'//itoa(k)
      end if
    end do
    if (cfg%run%t_end > 0.0_wp) return
    if (.not. rd%occ(io_run)%ok) return
    if (any_moving .and. all_stroke .and. .not. any_mass) then
      cfg%run%t_end = t_stop
    else if (any_mass) then
      call err_var(rd, io_run, 't_end', '', 'missing: required with a &wall of mass (a drop '// &
        'weight; &run end_at_release can end the run once it has rebounded)')
    else if (len(without) > 0) then
      call err_var(rd, io_run, 't_end', '', 'missing: required unless every moving &wall '// &
        'has a stroke (&wall '//without//' has none)')
    else
      call err_missing(rd, io_run, 't_end')
    end if
  end subroutine stroke_checks

  !> Given grid bounds (not fitted) contain every body.
  subroutine grid_bounds_checks(rd, cfg, io_grid, occ_body)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: io_grid, occ_body(:)
    integer :: k
    real(wp) :: lo(2), hi(2)
    if (rd%occ(io_grid)%ok .and. .not. cfg%grid%fitted) then
      do k = 1, size(cfg%bodies)
        if (.not. rd%occ(occ_body(k))%ok) cycle
        call body_box(cfg%bodies(k), lo, hi)
        if (any(lo < cfg%grid%lower)) call err_var(rd, io_grid, 'lower', &
          fmt_list(cfg%grid%lower), 'does not contain &body #'//itoa(k)// &
          ' (it reaches down to x = '//fmt_short(lo(1))//', y = '//fmt_short(lo(2))//')', &
          'lower <= '//fmt_short(lo(1))//', '//fmt_short(lo(2))//' for this body, '// &
          'or lower and upper not given (fitted)')
        if (any(hi > cfg%grid%upper)) call err_var(rd, io_grid, 'upper', &
          fmt_list(cfg%grid%upper), 'does not contain &body #'//itoa(k)// &
          ' (it reaches up to x = '//fmt_short(hi(1))//', y = '//fmt_short(hi(2))//')', &
          'upper >= '//fmt_short(hi(1))//', '//fmt_short(hi(2))//' for this body, '// &
          'or lower and upper not given (fitted)')
      end do
    end if
  end subroutine grid_bounds_checks

  !> Values that are usually a number in the wrong unit (mpm_units' rule), refused at their
  !! variable unless `&run check_units = .false.` (then the set-up warns of them). With only:
  !! those of occurrence io that need no other group, before its group's rules; without: those
  !! of the occurrences still ok (the values that the rules and other groups complete).
  subroutine unit_checks(rd, cfg, only)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in), optional :: only
    type(unit_issue_t), allocatable :: issues(:)
    integer :: j, io
    logical :: ok(rd%n_occ), body_ok(size(cfg%bodies))
    ok = rd%occ(1:rd%n_occ)%ok             ! (before this check's errors mark them)
    do j = 1, size(cfg%bodies)             ! the bodies whose values are complete
      io = occurrence(rd, 'body', j)
      body_ok(j) = io > 0
      if (io > 0) body_ok(j) = ok(io)
    end do
    call advice_unit_issues(cfg, issues, body_ok)
    do j = 1, size(issues)
      associate (u => issues(j))
        io = occurrence(rd, trim(u%group), max(u%k, 1))
        if (io == 0) cycle
        if (present(only)) then
          if (io /= only .or. u%others) cycle
        end if
        if (.not. ok(io)) cycle             ! its values may be unset
        call err_var(rd, io, trim(u%var), u%value, u%why, u%allowed// &
          ' (or &run check_units = .false. when the value is meant)')
      end associate
    end do
  end subroutine unit_checks

  !> &contact: the bodies named exist, and no pair (nor 0, 0) is named twice.
  subroutine contact_checks(rd, cfg, occ_con)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: occ_con(:)
    integer :: k, j, nb, b(2)
    nb = size(cfg%bodies)
    do k = 1, size(cfg%contacts)
      if (.not. rd%occ(occ_con(k))%ok) cycle
      b = cfg%contacts(k)%bodies
      if (maxval(b) > nb) then
        call err_var(rd, occ_con(k), 'bodies', itoa(b(1))//', '//itoa(b(2)), 'there is no '// &
          '&body #'//itoa(maxval(b))//' (the file has '//itoa(nb)//')', 'two different '// &
          'bodies from 1 to '//itoa(nb)//', or 0, 0 for every pair not named elsewhere')
        cycle
      end if
      do j = 1, k - 1
        if (.not. rd%occ(occ_con(j))%ok) cycle
        if (same_pair(cfg%contacts(j)%bodies, b)) then
          call err_var(rd, occ_con(k), 'bodies', itoa(b(1))//', '//itoa(b(2)), &
            'this pair is already named by &contact #'//itoa(j)//' (line '// &
            itoa(rd%occ(occ_con(j))%line)//')', 'each pair of bodies (and 0, 0) in one '// &
            '&contact only')
          exit
        end if
      end do
    end do
  end subroutine contact_checks

  !> The same unordered pair of bodies.
  pure logical function same_pair(a, b)
    integer, intent(in) :: a(2), b(2)
    same_pair = (a(1) == b(1) .and. a(2) == b(2)) .or. (a(1) == b(2) .and. a(2) == b(1))
  end function same_pair

  !> A fixed time step must not exceed the stable limit at cfl = 1; no time step, fixed or from
  !! cfl (at least its smallest automatic value), so small that t + dt would round to t.
  subroutine check_time_step(rd, cfg, io_run)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: io_run
    integer :: k, kc
    real(wp) :: cds(size(cfg%materials)), cd, vmax, dt_lim, cfl
    character(len=:), allocatable :: which
    if (size(cfg%materials) == 0) return
    do k = 1, size(cfg%materials)          ! dilatational wave speeds
      cds(k) = material_wave_speed(material_from(cfg%materials(k), cfg%solver%mass_scale))
    end do
    kc = maxloc(cds, dim=1)
    cd = cds(kc)
    vmax = max(0.0_wp, maxval([(norm2(cfg%bodies(k)%velocity), k = 1, size(cfg%bodies))]))
    dt_lim = time_step_dt(1.0_wp, cfg%grid%h, cd, vmax)
    if (.not. cfg%run%dt > 0.0_wp) then
      cfl = cfg%run%cfl
      which = 'cfl '
      if (.not. cfl > 0.0_wp) then
        cfl = cfl_margin*cfl_tried_min/stiffest_penalty(cfg)
        which = 'the smallest automatic cfl, '
      end if
      if (cfl*dt_lim < cfg%run%t_end*epsilon(1.0_wp)) call err_var(rd, io_run, 't_end', &
        fmt_real(cfg%run%t_end), 'the time step, about '//fmt_short(cfl*dt_lim)//' s ('//which// &
        fmt_short(cfl)//' x h / (c_d + v_max), c_d = '//fmt_short(cd)//' m/s of &material #'// &
        itoa(kc)//'), is so small that t + dt would round to t before t_end', 't_end <= '// &
        fmt_short(min(cfl*dt_lim/epsilon(1.0_wp), 1.0e6_wp))//' s, or a larger h, or a lower '// &
        'wave speed '// &
        '(nu further from 0.5)')
      return
    end if
    if (cfg%run%dt > dt_lim) call err_var(rd, io_run, 'dt', fmt_real(cfg%run%dt), &
      'above the stable limit h / (c_d + v_max) = '//fmt_short(dt_lim)//' s at cfl = 1 '// &
      '(h = '//fmt_short(cfg%grid%h)//' m; c_d = sqrt((lambda + 2 mu)/rho) = '// &
      fmt_short(cd)//' m/s of &material #'//itoa(kc)//'; v_max = '//fmt_short(vmax)// &
      ' m/s)', '0 < dt <= '//fmt_short(dt_lim)//' [s], or dt = 0 (time step from cfl)')
    ! more steps than double precision counts: t + dt would round to t, the run never end
    if (cfg%run%dt < cfg%run%t_end*epsilon(1.0_wp)) call err_var(rd, io_run, 'dt', &
      fmt_real(cfg%run%dt), 't_end / dt = '//fmt_short(cfg%run%t_end/cfg%run%dt)// &
      ' steps, more than double precision counts: the time t + dt would round to t before '// &
      't_end = '//fmt_short(cfg%run%t_end)//' s and the run would never end', 't_end x '// &
      fmt_short(epsilon(1.0_wp))//' = '//fmt_short(cfg%run%t_end*epsilon(1.0_wp))// &
      ' <= dt <= '//fmt_short(dt_lim)//' [s], or dt = 0 (time step from cfl)')
  end subroutine check_time_step


end module mpm_config_check
