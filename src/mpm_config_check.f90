!> The checks of the input that span groups: defaults that depend on other groups, material
!! references, the given grid bounds, the fixed time step.
! SPDX-License-Identifier: MIT
module mpm_config_check
  use mpm_kinds, only: wp
  use mpm_constants, only: SHAPE_DISC, BASIS_CPDI2, SCHEME_MUSL, PLANE_STRAIN, SHAPE_RING, SHAPE_RECT, &
                           SECTOR_HALF, SECTOR_QUARTER, VOLUMETRIC_FBAR, VOLUMETRIC_FBARWALL, &
                           PLANE_STRESS, MODEL_NEOHOOKEAN
  use mpm_config_types, only: config_t
  use mpm_bodies, only: body_box
  use mpm_config_text, only: lower, itoa, quote, file_stem, fmt_short, fmt_vec, fmt_real
  use mpm_config_table, only: n_groups
  use mpm_config_lexer, only: reader_t, occurrence
  use mpm_config_values, only: err_var, warn_var, err_missing
  use mpm_walls, only: wall_t, wall_stroke_setup, wall_end_time, wall_stroke_travel
  use mpm_units, only: advice_unit_issues, unit_issue_t
  use mpm_symmetry, only: symmetry_checks
  use mpm_placement, only: placement_checks
  use mpm_material, only: material_from, material_wave_speed
  use mpm_time_step, only: time_step_dt
  implicit none
  private
  public :: cross_checks

contains

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
    if (len_trim(cfg%run%title) == 0) cfg%run%title = file_stem(rd%file)
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
      do j = 1, k - 1
        if (lower(trim(cfg%materials(j)%name)) == lower(trim(cfg%materials(k)%name))) then
          call err_var(rd, occ_mat(k), 'name', quote(trim(cfg%materials(k)%name)), &
            'already used by &material #'//itoa(j)//' (line '// &
            itoa(rd%occ(occ_mat(j))%line)//')', 'a name that no other &material uses')
          exit
        end if
      end do
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
      id = 0
      do j = 1, size(cfg%materials)
        if (lower(want) == lower(trim(cfg%materials(j)%name))) then
          id = j
          exit
        end if
      end do
      if (id > 0) then
        cfg%bodies(k)%material_id = id
        cfg%bodies(k)%material = cfg%materials(id)%name
      else if (all_named) then
        call err_var(rd, occ_body(k), 'material', quote(want), 'no &material has this name', &
          'the name of a &material: '//names_txt//' (or not given: the first material)')
      end if
    end do

    ! strokes reached, and t_end from them where it is not given
    if (io_run > 0) call stroke_checks(rd, cfg, io_run)

    ! given grid bounds contain every body
    if (io_grid > 0) call grid_bounds_checks(rd, cfg, io_grid, occ_body)

    ! a fixed time step must not exceed the stable limit at cfl = 1
    all_ok = io_run > 0 .and. io_grid > 0 .and. size(cfg%materials) > 0 .and. &
             size(cfg%bodies) > 0
    if (all_ok) all_ok = rd%occ(io_run)%ok .and. rd%occ(io_grid)%ok
    if (all_ok .and. io_solver > 0) all_ok = rd%occ(io_solver)%ok
    do k = 1, size(cfg%materials)
      if (all_ok) all_ok = rd%occ(occ_mat(k))%ok
    end do
    do k = 1, size(cfg%bodies)
      if (all_ok) all_ok = rd%occ(occ_body(k))%ok
    end do
    if (all_ok) call check_fixed_dt(rd, cfg, io_run)

    ! a half or quarter model: nothing may move across its mirror planes (mpm_symmetry)
    call symmetry_checks(rd, cfg)
    n0 = rd%n_err
    if (cfg%run%check_units) call unit_checks(rd, cfg)
    if (io_grid > 0 .and. rd%n_err == n0) then   ! bodies apart, in front of the walls
      if (rd%occ(io_grid)%ok) call placement_checks(rd, cfg, occ_body)
    end if

    call contact_checks(rd, cfg, occ_con)
  end subroutine cross_checks

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
    real(wp) :: t_stop
    character(len=:), allocatable :: without
    all_stroke = .true.
    any_moving = .false.
    any_mass = .false.
    t_stop = 0.0_wp
    without = ''
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
        call err_var(rd, io, 'stroke', fmt_real(w%stroke), 'not reached: the motion comes '// &
          'to rest after '//fmt_short(wall_stroke_travel(w, huge(1.0_wp)*1.0e-10_wp))// &
          ' m', 'a stroke the motion reaches, or a motion table that keeps moving')
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
          fmt_vec(cfg%grid%lower), 'does not contain &body #'//itoa(k)// &
          ' (it reaches down to x = '//fmt_short(lo(1))//', y = '//fmt_short(lo(2))//')', &
          'lower <= '//fmt_short(lo(1))//', '//fmt_short(lo(2))//' for this body, '// &
          'or lower and upper not given (fitted)')
        if (any(hi > cfg%grid%upper)) call err_var(rd, io_grid, 'upper', &
          fmt_vec(cfg%grid%upper), 'does not contain &body #'//itoa(k)// &
          ' (it reaches up to x = '//fmt_short(hi(1))//', y = '//fmt_short(hi(2))//')', &
          'upper >= '//fmt_short(hi(1))//', '//fmt_short(hi(2))//' for this body, '// &
          'or lower and upper not given (fitted)')
      end do
    end if
  end subroutine grid_bounds_checks

  !> Values that are usually a number in the wrong unit (mpm_units' rule), refused at their
  !! variable unless `&run check_units = .false.` (then the set-up warns of them).
  subroutine unit_checks(rd, cfg)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    type(unit_issue_t), allocatable :: issues(:)
    integer :: j, io
    logical :: ok(rd%n_occ)
    call advice_unit_issues(cfg, issues)
    ok = rd%occ(1:rd%n_occ)%ok             ! (before this check's errors mark them)
    do j = 1, size(issues)
      associate (u => issues(j))
        io = occurrence(rd, trim(u%group), max(u%k, 1))
        if (io == 0) cycle
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

  !> A fixed time step must not exceed the stable limit at cfl = 1.
  subroutine check_fixed_dt(rd, cfg, io_run)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: io_run
    integer :: k, kc
    real(wp) :: cds(size(cfg%materials)), cd, vmax, dt_lim
    if (.not. cfg%run%dt > 0.0_wp .or. size(cfg%materials) == 0) return
    do k = 1, size(cfg%materials)          ! dilatational wave speeds
      cds(k) = material_wave_speed(material_from(cfg%materials(k), cfg%solver%mass_scale))
    end do
    kc = maxloc(cds, dim=1)
    cd = cds(kc)
    vmax = max(0.0_wp, maxval([(norm2(cfg%bodies(k)%velocity), k = 1, size(cfg%bodies))]))
    dt_lim = time_step_dt(1.0_wp, cfg%grid%h, cd, vmax)
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
  end subroutine check_fixed_dt

end module mpm_config_check
