!> Tests of mpm_config: exact round trips of every namelist, resolved defaults, the template of
!! default_config, and bad inputs (each must give stat = EXIT_INPUT and a message naming the
!! file line, the group and the variable).
! SPDX-License-Identifier: MIT
!
! Run from the repository root (it reads namelists/ and tests/bad_inputs/); scratch files go to
! the folder given as the first argument.
program test_config
  use testing, only: begin_test, check, check_close, finish_tests, scratch_dir
  use mpm_kinds, only: wp
  use mpm_strings, only: itoa
  use mpm_constants, only: EXIT_INPUT, EXIT_IO, max_table, BASIS_CPDI1, BASIS_CPDI2, &
                           SCHEME_MUSL, SCHEME_USF, PLANE_STRAIN, PLANE_STRESS, MODEL_J2, &
                           MODEL_ELASTIC, MODEL_FOAM, RATE_NONE, RATE_COWPER_SYMONDS, &
                           SHAPE_RING, SHAPE_RECT, SECTOR_FULL, SECTOR_HALF, SECTOR_QUARTER, &
                           CONTACT_COULOMB, shape_names, model_names
  use mpm_config_table, only: specs
  use mpm_config, only: config_t, read_config, write_config, write_config_unit, default_config, &
                        config_resolve
  use mpm_scene_builder, only: scene_new, scene_add_material, scene_add_ring, scene_add_wall
  implicit none

  character(len=*), parameter :: nml_files(5) = [character(len=32) :: &
    'namelists/default.nml', 'namelists/crush.nml', 'namelists/impact.nml', 'namelists/wave.nml', &
    'namelists/foam/foam_block.nml']
  character(len=*), parameter :: bad_files(42) = [character(len=32) :: &
    '01_empty', '02_missing_run', '03_only_run', '04_unknown_group', '05_unknown_variable', &
    '06_text_for_number', '07_integer_expected', '08_unquoted_text', '09_bad_enum', &
    '10_repeated_run', '11_cfl_range', '12_t_end_missing', '13_nu_range', &
    '14_sigma_y_missing', '15_radii_order', '16_material_undefined', '17_duplicate_material', &
    '18_normal_not_unit', '19_friction_without_coulomb', '20_motion_not_increasing', &
    '21_motion_length_mismatch', '22_nan_value', '23_dt_unstable', '24_grid_too_small', &
    '25_lower_without_upper', '26_n_circ_sector', '27_rect_missing_size', &
    '28_too_many_values', '29_unclosed_group', '30_text_outside_group', &
    '31_probe_point_missing', '32_several_errors', '33_missing_equals', '34_motion_too_long', &
    '36_logical_expected', '37_inf_value', '38_number_too_large', &
    '39_johnson_cook', '40_contact', '41_volumetric', '42_fbar_bodies', '55_filler']
  ! a valid scene to which the inline bad cases add one mistake
  character(len=*), parameter :: run_ok = '&run t_end = 1.0e-3 /'
  character(len=*), parameter :: grid_ok = '&grid h = 1.0e-3 /'
  character(len=*), parameter :: mat_ok = &
    '&material name = ''alu'', E = 70e9, nu = 0.33, rho = 2700, sigma_y = 150e6 /'
  character(len=*), parameter :: body_ok = '&body r_inner = 24e-3, r_outer = 26e-3 /'
  character(len=:), allocatable :: dir
  integer :: n_bad_inline = 0

  dir = scratch_dir()
  call test_round_trips()
  call test_defaults()
  call test_resolved_examples()
  call test_extreme_round_trip()
  call test_foam_round_trip()
  call test_default_config()
  call test_warnings()
  call test_resolve()
  call test_value_forms()
  call test_bad_inline()
  call test_several_at_once()
  call test_bad_files()
  call test_io_errors()
  call test_file_formats()
  call finish_tests('test_config')

contains

  ! ---------------------------------------------------------------------- round trips

  !> Every file in namelists/: read, write, read back: identical; the second echo is
  !! identical text to the first.
  subroutine test_round_trips()
    type(config_t) :: a, b
    integer :: k, stat
    character(len=:), allocatable :: msg, echo1, echo2, f1, f2
    call begin_test('round trip of namelists/*.nml')
    do k = 1, size(nml_files)
      call read_config(trim(nml_files(k)), a, stat, msg)
      call check(stat == 0, trim(nml_files(k))//' reads without error: '//msg)
      if (stat /= 0) cycle
      f1 = dir//'/echo1_'//itoa(k)//'.nml'
      f2 = dir//'/echo2_'//itoa(k)//'.nml'
      call write_config(a, f1, stat, msg)
      call check(stat == 0, 'write_config '//f1//': '//msg)
      call read_config(f1, b, stat, msg)
      call check(stat == 0, 'the echo of '//trim(nml_files(k))//' reads back: '//msg)
      if (stat /= 0) cycle
      call check(config_diff(a, b) == '', 'echo of '//trim(nml_files(k))// &
        ' reads back identical; differs in: '//config_diff(a, b))
      call write_config(b, f2, stat, msg)
      echo1 = file_text(f1)
      echo2 = file_text(f2)
      call check(echo1 == echo2, 'second echo of '//trim(nml_files(k))//' is the same text')
    end do
  end subroutine test_round_trips

  !> Foam: foam_alpha with a full 64-point curve, and nu_plastic with the law: read, echo, read
  !! back identical; config_resolve of the case read keeps it.
  subroutine test_foam_round_trip()
    type(config_t) :: a, b
    integer :: k, stat
    character(len=:), allocatable :: f, f2, msg
    character(len=2048), allocatable :: lines(:)
    call begin_test('round trip of foam materials')
    lines = [character(len=2048) :: run_ok, grid_ok, &
      '&material name = ''f1'', model = ''FOAM'', E = 1e9, nu = 0.3, rho = 230, foam_alpha = 1.5', &
      ' curve_strain =', ' curve_stress =', '/', &
      '&material name = ''f2'', model = ''foam'', E = 1e9, nu = 0.3, rho = 230, sigma_p = 1.6e6', &
      ' eps_d = 2.46, nu_plastic = -0.2, foam_gamma = 2e6, foam_alpha2 = 4e6, foam_beta = 3 /', &
      '&body material = ''f1'', r_inner = 24e-3, r_outer = 26e-3 /']
    do k = 1, max_table
      lines(4) = trim(lines(4))//' '//e17(real(k - 1, wp)*0.03_wp)//','
      lines(5) = trim(lines(5))//' '//e17(1.6e6_wp + real(k - 1, wp)**2*1.0e3_wp/3.0_wp)//','
    end do
    f = write_case('foam', lines)
    call read_config(f, a, stat, msg)
    call check(stat == 0, 'the foam case reads: '//msg)
    if (stat /= 0) return
    call check(a%materials(1)%model_id == MODEL_FOAM .and. a%materials(1)%n_curve == max_table &
      .and. a%materials(1)%foam_alpha == 1.5_wp .and. a%materials(1)%sigma_p < 0.0_wp, &
      'f1: foam, 64 curve points, foam_alpha, no sigma_p')
    call check(a%materials(2)%n_curve == 0 .and. a%materials(2)%nu_plastic == -0.2_wp .and. &
      a%materials(2)%foam_alpha < 0.0_wp .and. a%materials(2)%foam_beta == 3.0_wp .and. &
      a%materials(2)%eps_d == 2.46_wp, 'f2: the law, nu_plastic')
    f2 = dir//'/foam_echo.nml'
    call write_config(a, f2, stat, msg)
    call read_config(f2, b, stat, msg)
    call check(stat == 0, 'the foam echo reads back: '//msg)
    if (stat /= 0) return
    call check(config_diff(a, b) == '', 'the foam echo reads back identical; differs in: '// &
      config_diff(a, b))
    call config_resolve(b, stat, msg)
    if (stat == 0) msg = config_diff(a, b)
    call check(msg == '', 'config_resolve keeps the foam case: '//msg)
  end subroutine test_foam_round_trip

  !> Extreme and awkward values survive write + read exactly.
  subroutine test_extreme_round_trip()
    type(config_t) :: a, b
    integer :: k, stat
    character(len=:), allocatable :: f, f2, msg
    character(len=2048), allocatable :: lines(:)
    real(wp) :: third
    call begin_test('round trip of awkward values')
    third = 1.0_wp/3.0_wp
    lines = [character(len=2048) :: &
      '&run title = ''it''''s a "test"'', output_dir = ''a/b c/d''', &
      ' t_end = '//e17(1.0e-14_wp*third), &      ! the program's limits: 1e-15 s, 1e3 m
      ' cfl = '//e17(0.1_wp + 0.2_wp), &
      ' depth = '//e17(1.0e3_wp - third), &
      ' gravity = -0.0, '//e17(-9.81_wp*third), &   ! along the mirror plane of body 2
      ' threads = 3, history_every = 1e-7, check_units = F /', &   ! lower = -1, -2 (m)
      '&solver basis = ''CPDI1'', scheme = ''Usf'', plane = ''STRESS''', &
      ' flip = '//e17(0.99_wp), &
      ' mass_scale = 1e4, damping = 123.456, deterministic = T /', &
      '&grid h = 0.37e-3, lower = -1, -2, upper = 3.5, 4 /', &
      '&material name = ''steel'', model = ''ELASTIC'', nu = 0', &
      ' E = '//e17(third*1.0e11_wp)//', rho = '//e17(7.8e3_wp*third), &
      ' sigma_y = 2.5e8, rate_law = ''none'', cs_d = 6500, cs_q = 4 /', &
      '&material name = ''alu'', E = 7e10, nu = 0.499999, rho = 2.7e3', &
      ' sigma_y = 1.5e8, hardening = 1.0000000000000002e-3, rate_law = ''Cowper_Symonds'' /', &
      '&body shape = ''rect'', material = ''ALU'', center = 1.5, 0.25', &
      ' size = 0.5, 0.25, n_x = 7, n_y = 3, velocity = -0.0, 1e-12 /', &
      '&body material = ''steel'', center = 1, 1, r_inner = 0.1, r_outer = 0.2', &
      ' n_thick = 3, n_circ = 10, sector = ''HALF'' /', &
      '&wall point = 0, -2, normal = 0.6, 0.8, contact = ''Coulomb''', &
      ' friction = 0.3, velocity = 0, 1, ramp = 1e-4 /', &
      '&wall point = 0, 0, normal = 0, 1', &
      ' motion_t =', ' motion_f =', '/', &
      '&probe point = 1.1, 2.2 /', &
      '&probe point = -3.3e-3, 4.4e-4 /']
    do k = 1, max_table                        ! a full table on one line each
      lines(23) = trim(lines(23))//' '//e17(real(k - 1, wp)*third*1.0e-6_wp)//','
      lines(24) = trim(lines(24))//' '//e17(sin(real(k, wp)))
    end do
    f = write_case('extreme', lines)
    call read_config(f, a, stat, msg)
    call check(stat == 0, 'awkward file reads: '//msg)
    if (stat /= 0) return
    call check(a%run%title == 'it''s a "test"', 'quotes in a title: '//trim(a%run%title))
    call check(a%run%t_end == 1.0e-14_wp*third .and. a%run%depth == 1.0e3_wp - third, &
      'near the limits, all 17 digits')
    call check(a%run%cfl == 0.1_wp + 0.2_wp, '0.1 + 0.2 exactly')
    call check(a%solver%basis == 'cpdi1' .and. a%solver%basis_id == BASIS_CPDI1 .and. &
      a%solver%scheme_id == SCHEME_USF .and. a%solver%plane_id == PLANE_STRESS, &
      'enumerations lower-cased with their codes')
    call check(.not. a%grid%fitted, 'lower and upper given: not fitted')
    call check(a%bodies(1)%material == 'alu' .and. a%bodies(1)%material_id == 2, &
      'material reference is case-insensitive and resolved to the name')
    call check(a%bodies(2)%sector_id == SECTOR_HALF .and. a%bodies(1)%shape_id == SHAPE_RECT, &
      'sector and shape codes')
    call check(a%materials(2)%rate_law_id == RATE_COWPER_SYMONDS .and. &
      a%materials(1)%model_id == MODEL_ELASTIC, 'rate law and model codes')
    call check(a%walls(2)%n_motion == max_table, '64 table points: n_motion = 64')
    call check(a%walls(1)%contact_id == CONTACT_COULOMB, 'contact code')
    f2 = dir//'/extreme_echo.nml'
    call write_config(a, f2, stat, msg)
    call check(stat == 0, 'write awkward echo: '//msg)
    call read_config(f2, b, stat, msg)
    call check(stat == 0, 'awkward echo reads back: '//msg)
    if (stat /= 0) return
    call check(config_diff(a, b) == '', 'awkward values read back identical; '// &
      'differs in: '//config_diff(a, b))
  end subroutine test_extreme_round_trip

  ! ---------------------------------------------------------------------- defaults

  !> A minimal file gets every default of docs/input.md.
  subroutine test_defaults()
    type(config_t) :: c
    integer :: stat
    character(len=:), allocatable :: msg, f
    call begin_test('defaults of a minimal file')
    f = write_case('minimal_case', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok])
    call read_config(f, c, stat, msg)
    call check(stat == 0, 'minimal file reads: '//msg)
    if (stat /= 0) return
    call check(c%run%title == 'minimal_case', 'title = file name stem: '//trim(c%run%title))
    call check(c%run%output_dir == 'out/minimal_case', 'output_dir = out/<title>: '// &
      trim(c%run%output_dir))
    call check(c%run%cfl == 0.0_wp, 'cfl default 0 (automatic)')
    call check(c%run%dt == 0.0_wp .and. c%run%history_every == 0.0_wp .and. &
      c%run%snapshot_every == 0.0_wp .and. c%run%checkpoint_every == 0.0_wp, 'interval defaults')
    call check(c%run%depth == 1.0_wp .and. all(c%run%gravity == 0.0_wp) .and. &
      c%run%threads == 0, 'depth, gravity, threads defaults')
    call check(c%solver%basis == 'cpdi2' .and. c%solver%basis_id == BASIS_CPDI2, 'basis default')
    call check(c%solver%scheme_id == SCHEME_MUSL .and. c%solver%plane_id == PLANE_STRAIN, &
      'scheme and plane defaults (no &solver group)')
    call check(c%solver%flip == 1.0_wp .and. c%solver%mass_scale == 1.0_wp .and. &
      c%solver%damping == 0.0_wp .and. .not. c%solver%deterministic, 'solver number defaults')
    call check(c%grid%fitted, 'no lower/upper: fitted')
    call check(c%materials(1)%model_id == MODEL_J2 .and. c%materials(1)%rate_law_id == RATE_NONE, &
      'model j2 and rate_law none by default')
    call check(c%materials(1)%hardening == 0.0_wp .and. c%materials(1)%cs_d == 40.4_wp .and. &
      c%materials(1)%cs_q == 5.0_wp, 'hardening, cs_d, cs_q defaults')
    call check(c%bodies(1)%shape_id == SHAPE_RING .and. c%bodies(1)%sector_id == SECTOR_FULL, &
      'ring, full sector by default')
    call check(c%bodies(1)%material == 'alu' .and. c%bodies(1)%material_id == 1, &
      'material not given: the first material')
    call check(c%bodies(1)%n_thick == 16 .and. c%bodies(1)%n_circ == 0 .and. &
      all(c%bodies(1)%center == 0.0_wp) .and. all(c%bodies(1)%velocity == 0.0_wp), &
      'n_thick 16, n_circ 0, centre and velocity 0')
    call check(size(c%walls) == 0 .and. size(c%probes) == 0, 'no walls, no probes: size 0')
  end subroutine test_defaults

  !> What the shipped examples resolve to.
  subroutine test_resolved_examples()
    type(config_t) :: c
    integer :: stat
    character(len=:), allocatable :: msg
    call begin_test('resolved examples')
    call read_config('namelists/wave.nml', c, stat, msg)
    call check(stat == 0, 'wave.nml reads: '//msg)
    if (stat == 0) then
      call check(size(c%probes) == 7, '7 probes in wave.nml')
      call check(c%walls(1)%n_motion == 4, '4 table points in wave.nml')
      call check_close(c%walls(1)%motion_t(1:4), [0.0_wp, 2.0e-6_wp, 1.0e-5_wp, 1.2e-5_wp], &
        'wave motion_t')
      call check_close(c%walls(1)%motion_f(1:4), [0.0_wp, 1.0_wp, 1.0_wp, 0.0_wp], &
        'wave motion_f')
      call check_close(c%probes(2)%point, [0.0125_wp, 0.004349365_wp], 'probe at 30 degrees', &
        rtol=1.0e-15_wp)
    end if
    call read_config('namelists/crush.nml', c, stat, msg)
    call check(stat == 0, 'crush.nml reads: '//msg)
    if (stat == 0) then
      call check(size(c%walls) == 1 .and. c%walls(1)%velocity(2) == -2.5_wp .and. &
        c%walls(1)%ramp == 5.0e-4_wp .and. c%walls(1)%stroke == 15.0e-3_wp .and. c%bodies(1)%sector_id == SECTOR_QUARTER, &
        'crush: quarter ring, top platen at -2.5 m/s with ramp 5e-4 s, stroke 15 mm')
      call check_close(c%bodies(1)%r_outer - c%bodies(1)%r_inner, 1.48e-3_wp, &
        'crush: wall 1.48 mm', rtol=1.0e-12_wp)
      call check_close(c%walls(1)%point(2), 2.0_wp*c%bodies(1)%r_outer, &
        'crush: top platen at D_outer', rtol=1.0e-15_wp)
    end if
  end subroutine test_resolved_examples

  !> The template of default_config prints every group; read back it misses exactly the
  !! required values; with them filled in it round-trips.
  subroutine test_default_config()
    type(config_t) :: d, b
    integer :: stat, u, ios
    character(len=:), allocatable :: msg, f, text
    character(len=256) :: iomsg
    character(len=40), parameter :: missing(12) = [character(len=40) :: &
      '&run: t_end: missing', '&grid: h: missing', '&material #1: name: missing', &
      '&material #1: E: missing', '&material #1: nu: missing', '&material #1: rho: missing', &
      '&material #1: sigma_y: missing', '&body #1: r_inner: missing', &
      '&body #1: r_outer: missing', '&wall #1: point: missing', '&wall #1: normal: missing', &
      '&probe #1: point: missing']
    integer :: k
    call begin_test('default_config')
    call default_config(d)
    f = dir//'/defaults.nml'
    open(newunit=u, file=f, status='replace', action='write', iostat=ios, iomsg=iomsg)
    call check(ios == 0, 'open '//f//': '//trim(iomsg))
    call write_config_unit(d, u, stat, msg)
    close(u, iostat=ios, iomsg=iomsg)
    call check(stat == 0, 'write_config_unit of the template: '//msg)
    text = file_text(f)
    do k = 1, 7
      call check(index(text, new_line('a')//'&'//trim(group_of(k))) > 0, &
        'template holds &'//trim(group_of(k)))
    end do
    call check(index(text, '! t_end = ...') > 0, 'required t_end written as a comment')
    call read_config(f, b, stat, msg)
    call check(stat == EXIT_INPUT, 'the template alone is not a valid case')
    do k = 1, size(missing)
      call check(index(msg, trim(missing(k))) > 0, 'template read back reports: '// &
        trim(missing(k)))
    end do
    call check(count_lines(msg) == size(missing), 'only the required values are missing ('// &
      itoa(count_lines(msg))//' messages)')
    d%run%title = 'template'
    d%run%output_dir = 'out/template'
    d%run%t_end = 1.0e-3_wp
    d%grid%h = 1.0e-3_wp
    d%materials(1)%name = 'm'
    d%materials(1)%E = 1.0e9_wp
    d%materials(1)%nu = 0.25_wp
    d%materials(1)%rho = 1000.0_wp
    d%materials(1)%sigma_y = 1.0e6_wp
    d%bodies(1)%r_inner = 0.5_wp
    d%bodies(1)%r_outer = 0.6_wp
    d%bodies(1)%material = 'm'
    d%walls(1)%point = [0.0_wp, -1.0_wp]
    d%walls(1)%normal = [0.0_wp, 1.0_wp]
    d%probes(1)%point = [0.0_wp, 0.5_wp]
    call write_config(d, f, stat, msg)
    call read_config(f, b, stat, msg)
    call check(stat == 0, 'filled template reads: '//msg)
    if (stat == 0) call check(config_diff(d, b) == '', 'filled template round trip; '// &
      'differs in: '//config_diff(d, b))
  end subroutine test_default_config

  !> Advice that is not an error comes back in the optional warnings.
  subroutine test_warnings()
    type(config_t) :: c
    integer :: stat
    character(len=:), allocatable :: msg, warn, f
    call begin_test('warnings')
    f = write_case('warn', [character(len=100) :: run_ok, '&grid h = 3e-3 /', mat_ok, body_ok, &
      '&wall point = 0, -0.03, normal = 0, 1, ramp = 1e-4', &
      '  motion_t = 0, 1e-4, motion_f = 0, 1 /'])
    call read_config(f, c, stat, msg, warn)
    call check(stat == 0, 'warnings do not fail the read: '//msg)
    call check(index(warn, 'warn.nml:2:') == 0, 'h >= wall thickness is advice (--check), '// &
      'not the reader''s: '//warn)
    call check(index(warn, 'warn.nml:5: &wall #1: ramp = 1e-4: the motion table replaces it. '// &
      'Set ramp = 0 (docs/input.md#wall)') > 0, 'ramp with a motion table is a warning: '//warn)
    call test_other_shape()
  end subroutine test_warnings

  !> The variables of another body shape (the table's `only`): a warning that names those
  !! given (whatever their value but the reader's start value), none otherwise; the echo leaves them out with one comment line that names the shape they are
  !! for.
  subroutine test_other_shape()
    type(config_t) :: c
    integer :: stat
    character(len=:), allocatable :: msg, warn, f, echo
    integer :: k
    character(len=*), parameter :: rect = '&body shape = ''rect'', size = 4e-3, 4e-3, n_x = 4, '// &
      'n_y = 4'
    f = write_case('shape1', [character(len=160) :: run_ok, grid_ok, mat_ok, &
      '&body r_inner = 24e-3, r_outer = 26e-3, n_y = 3 /', rect//', sector = ''half'' /', &
      rect//', center = 0, 1e-2, self_contact = .false. /', rect//', center = 0, 2e-2 /', &
      rect//', center = 0, 3e-2, self_contact = .true. /', &
      '&body center = 0, 1, r_inner = 24e-3, r_outer = 26e-3, size = 0, 1 /'])
    call read_config(f, c, stat, msg, warn)
    call check(stat == 0, 'other shapes'' variables do not fail the read: '//msg)
    call check(index(warn, 'shape1.nml:4: &body #1: n_y is ignored for shape = ''ring''') > 0, &
      'n_y of a ring is warned of, and only it: '//warn)
    call check(index(warn, 'shape1.nml:5: &body #2: sector is ignored for shape = ''rect''') > 0, &
      'sector of a rect, and only it')
    call check(index(warn, 'shape1.nml:6:') == 0, 'self_contact = .false. (its default) of '// &
      'a rect is not warned of')
    call check(index(warn, 'shape1.nml:7:') == 0, 'a rect without ring variables')
    call check(index(warn, 'shape1.nml:8: &body #5: self_contact is ignored for shape = '// &
      '''rect''') > 0, 'self_contact = .true. of a rect')
    call check(index(warn, 'shape1.nml:9: &body #6: size is ignored for shape = ''ring''') > 0, &
      'size = 0, 1 of a ring (one component given)')
    call write_config(c, dir//'/shape1_echo.nml', stat, msg)
    echo = file_text(dir//'/shape1_echo.nml')
    call check(count_of(echo, '  ! size, n_x, n_y, vertices, thickness, corner_radius, '// &
      'n_cells, cell_l, cell_h, cell_angle, walls_file, fills, fill_gap: not for rings') == 2, &
      'the echo names the other shapes'' variables once per ring')
    call check(count_of(echo, '  ! r_inner, r_outer, n_thick, n_circ, sector, self_contact: '// &
      'not for rectangles') == 4, 'the echo names the rings'' variables once per rectangle')
    call check(count_of(echo, 'self_contact =') == 0, 'no ring here has self-contact: '// &
      'self_contact is left out without a line')
    do k = 1, size(specs)                    ! the echo names the shape from the row's `only`
      if (len_trim(specs(k)%only) > 0 .and. specs(k)%group == 'body') call check( &
        words_in(specs(k)%only, shape_names), 'the row '//trim(specs(k)%name)// &
        ' is only for shapes of shape_names: '//specs(k)%only)
      if (len_trim(specs(k)%only) > 0 .and. specs(k)%group /= 'body') call check( &
        specs(k)%group == 'material' .and. words_in(specs(k)%only, model_names), 'the row '// &
        trim(specs(k)%name)//' is only for models of model_names: '//specs(k)%only)
    end do
  end subroutine test_other_shape

  !> Whether every blank-separated word of `list` is one of `names`.
  pure logical function words_in(list, names)
    character(len=*), intent(in) :: list, names(:)
    integer :: p, q
    character(len=len(list)) :: rest
    words_in = .true.
    rest = adjustl(list)
    do while (len_trim(rest) > 0)
      q = index(rest, ' ')
      p = findloc(names, rest(1:q-1), 1)
      words_in = words_in .and. p > 0
      rest = adjustl(rest(q:))
    end do
  end function words_in

  !> How often `part` occurs in `text`.
  pure integer function count_of(text, part) result(n)
    character(len=*), intent(in) :: text, part
    integer :: i, k
    n = 0
    i = 1
    do
      k = index(text(i:), part)
      if (k == 0) exit
      n = n + 1
      i = i + k + len(part) - 1
    end do
  end function count_of

  !> A case built in code (mpm_scene_builder) and resolved by config_resolve equals the same
  !! case read from a file (the echoes are the same text); a mistake in a built case gives the
  !! file's message (less the line).
  subroutine test_resolve()
    type(config_t) :: a, b
    integer :: stat
    character(len=:), allocatable :: msg, f, ta, tb
    call begin_test('config_resolve')
    f = write_case('built', [character(len=100) :: &
      '&run t_end = 1.0e-3 /', '&grid h = 1.0e-3 /', &
      '&material name = ''alu'', E = 70e9, nu = 0.33, rho = 2700, sigma_y = 150e6 /', &
      '&body r_inner = 24e-3, r_outer = 26e-3, n_thick = 4, velocity = 0, -30 /', &
      '&wall point = 0, -0.03, normal = 0, 1 /'])
    call read_config(f, a, stat, msg)
    call check(stat == 0, 'the file reads: '//msg)
    b = scene_new('built', 1.0e-3_wp, 1.0e-3_wp)
    b%file = f
    call scene_add_material(b, 'alu', MODEL_J2, 70.0e9_wp, 0.33_wp, 2700.0_wp, 150.0e6_wp)
    call scene_add_ring(b, [0.0_wp, 0.0_wp], 24.0e-3_wp, 26.0e-3_wp, 4, [0.0_wp, -30.0_wp])
    call scene_add_wall(b, [0.0_wp, -0.03_wp], [0.0_wp, 1.0_wp])
    b%run%output_dir = ''
    call config_resolve(b, stat, msg)
    call check(stat == 0, 'the built case resolves: '//msg)
    call write_config(a, dir//'/read_echo.nml', stat, msg)
    call write_config(b, dir//'/built_echo.nml', stat, msg)
    ta = file_text(dir//'/read_echo.nml')
    tb = file_text(dir//'/built_echo.nml')
    call check(len(ta) > 0 .and. ta == tb, 'built + resolved = read: '//tb)
    b%materials(1)%nu = 0.6_wp
    b%run%t_end = -1.0_wp
    call config_resolve(b, stat, msg)
    call check(stat == EXIT_INPUT, 'nu = 0.6 and no t_end fail')
    call check(index(msg, '&material #1: nu = 0.6: out of range; allowed: a real number '// &
      'with 0 <= nu < 0.5 (required)') > 0, 'nu out of range, as from a file: '//msg)
    call check(index(msg, '&run: t_end: missing (required)') > 0, 't_end missing: '//msg)
  end subroutine test_resolve

  !> Values as gfortran's namelist reader takes them (the table-driven reader reads the values
  !! itself): a null value keeps the default, `r*x` repeats, a later assignment wins, a
  !! subscript fills from its index, a text without quotes that starts with a digit is text.
  subroutine test_value_forms()
    type(config_t) :: c
    integer :: stat
    character(len=:), allocatable :: msg, f
    call begin_test('value forms')
    f = write_case('forms', [character(len=100) :: &
      '&run t_end = 1.0e-3, gravity = , -9.8, title = 123, depth = 2*0.5 /', grid_ok, mat_ok, &
      '&body r_inner = 24e-3, r_outer = 26e-3, center(2) = 0.5, velocity = 2*3.0 /', &
      '&wall point = 0, 0, normal = 0, 1, friction = 0.5, friction = 0 /'])
    call read_config(f, c, stat, msg)
    call check(stat /= 0, 'depth = 2*0.5 is two values for one: '//msg)
    call check(index(msg, 'depth = 2*0.5: too many values (2 given, 1 allowed)') > 0, msg)
    f = write_case('forms', [character(len=100) :: &
      '&run t_end = 1.0e-3, gravity = , -9.8, title = 123 /', grid_ok, mat_ok, &
      '&body r_inner = 24e-3, r_outer = 26e-3, center(2) = 0.5, velocity = 2*3.0 /', &
      '&wall point = 0, 0, normal = 0, 1, friction = 0.5, friction = 0 /'])
    call read_config(f, c, stat, msg)
    call check(stat == 0, 'value forms read: '//msg)
    if (stat /= 0) return
    call check(all(c%run%gravity == [0.0_wp, -9.8_wp]), 'null value keeps the default 0')
    call check(c%run%title == '123', 'title = 123 is the text 123')
    call check(all(c%bodies(1)%center == [0.0_wp, 0.5_wp]), 'center(2) = 0.5')
    call check(all(c%bodies(1)%velocity == [3.0_wp, 3.0_wp]), 'velocity = 2*3.0')
    call check(c%walls(1)%friction == 0.0_wp, 'the later friction wins')
    f = write_case('forms2', [character(len=100) :: run_ok//' '//grid_ok, mat_ok, body_ok, &
      '&solver, basis = ''cpdi1'' /', &
      '&wall point = 0.5,   ! x, and a comment after the comma', '  -0.25  ! y', &
      '  normal = 0, 1 /'])
    call read_config(f, c, stat, msg)
    call check(stat == 0, 'two groups on one line, a comment after a comma: '//msg)
    if (stat /= 0) return
    call check(c%grid%h == 1.0e-3_wp .and. all(c%walls(1)%point == [0.5_wp, -0.25_wp]), &
      'both groups of the line read; the values go on after the comment')
    call check(c%solver%basis_id == BASIS_CPDI1, 'a comma after the group name is allowed')
  end subroutine test_value_forms

  ! ---------------------------------------------------------------------- bad inputs

  !> Bad inputs written here, each with the exact position, group and variable expected.
  subroutine test_bad_inline()
    call begin_test('bad inputs (inline)')
    call bad('b_text_in_quotes', [character(len=100) :: '&run', '  t_end = ''abc''', '/', &
      grid_ok, mat_ok, body_ok], [character(len=100) :: &
      ':2: &run: t_end = ''abc'': ''abc'' is text in quotes, not a real number'])
    call bad('b_threads', [character(len=100) :: '&run t_end = 1e-3', ' threads = -1 /', &
      grid_ok, mat_ok, body_ok], [character(len=100) :: ':2: &run: threads = -1: out of range', &
      'allowed: an integer >= 0'])
    call bad('b_depth', [character(len=100) :: '&run t_end = 1e-3, depth = 0 /', grid_ok, &
      mat_ok, body_ok], [character(len=100) :: ':1: &run: depth = 0: out of range'])
    call bad('b_history', [character(len=100) :: '&run t_end = 1e-3', '', &
      '  history_every = -1e-3 /', grid_ok, mat_ok, body_ok], [character(len=100) :: &
      ':3: &run: history_every = -1e-3: out of range', 'allowed: a real number >= 0 [s]'])
    call bad('b_checkpoint_nan', [character(len=100) :: '&run t_end = 1e-3', &
      '  checkpoint_every = NaN /', grid_ok, mat_ok, body_ok], [character(len=100) :: &
      ':2: &run: checkpoint_every = NaN: not a finite number'])
    call bad('b_dt_negative', [character(len=100) :: '&run t_end = 1e-3, dt = -1 /', grid_ok, &
      mat_ok, body_ok], [character(len=100) :: ':1: &run: dt = -1: out of range'])
    call bad('b_gravity_inf', [character(len=100) :: '&run t_end = 1e-3, gravity(2) = -Inf /', &
      grid_ok, mat_ok, body_ok], [character(len=100) :: ':1: &run: gravity(2) = -Inf (so '// &
      'gravity = 0.0, -Infinity): not finite numbers'])
    call bad('b_plane', [character(len=100) :: run_ok, '&solver', ' plane = ''axisymmetric''', &
      '/', grid_ok, mat_ok, body_ok], [character(len=100) :: &
      ':3: &solver: plane = ''axisymmetric'': not an allowed value', &
      'allowed: ''strain'', ''stress'' (default ''strain'')'])
    call bad('b_scheme', [character(len=100) :: run_ok, '&solver scheme = ''USX'' /', grid_ok, &
      mat_ok, body_ok], [character(len=100) :: &
      ':2: &solver: scheme = ''USX'': not an allowed value', '''usl'', ''usf'', ''musl'''])
    call bad('b_flip', [character(len=100) :: run_ok, '&solver flip = 1.5 /', grid_ok, mat_ok, &
      body_ok], [character(len=100) :: ':2: &solver: flip = 1.5: out of range', &
      '0 <= flip <= 1'])
    call bad('b_mass_scale', [character(len=100) :: run_ok, '&solver mass_scale = 0.5 /', &
      grid_ok, mat_ok, body_ok], [character(len=100) :: &
      ':2: &solver: mass_scale = 0.5: out of range', 'a real number >= 1'])
    call bad('b_damping', [character(len=100) :: run_ok, '&solver damping = -1 /', grid_ok, &
      mat_ok, body_ok], [character(len=100) :: ':2: &solver: damping = -1: out of range'])
    call bad('b_solver_twice', [character(len=100) :: run_ok, '&solver /', grid_ok, mat_ok, &
      body_ok, '&solver flip = 0 /'], [character(len=100) :: &
      ':6: &solver: group given 2 times (lines 2, 6)'])
    call bad('b_grid_twice', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, grid_ok], &
      [character(len=100) :: ':5: &grid: group given 2 times (lines 2, 5)'])
    call bad('b_h_missing', [character(len=100) :: run_ok, '&grid /', mat_ok, body_ok], &
      [character(len=100) :: ':2: &grid: h: missing (required)'])
    call bad('b_lower_upper', [character(len=100) :: run_ok, '&grid h = 1e-3', &
      ' lower = 0, 0', ' upper = 1, -1 /', mat_ok, body_ok], [character(len=100) :: &
      ':4: &grid: upper = 1, -1: not above lower = 0.0, 0.0'])
    call bad('b_model', [character(len=100) :: run_ok, grid_ok, &
      '&material name = ''a'', model = ''plastic'', E = 1e9, nu = 0.3, rho = 1 /', body_ok], &
      [character(len=100) :: ':3: &material #1: model = ''plastic'': not an allowed value', &
      '''elastic'', ''neohookean'', ''j2'''])
    call bad('b_rho_zero', [character(len=100) :: run_ok, grid_ok, '&material name = ''a''', &
      ' E = 1e9, nu = 0.3, sigma_y = 1e6', ' rho = 0 /', body_ok], [character(len=100) :: &
      ':5: &material #1: rho = 0: out of range', 'a real number > 0 [kg/m^3]'])
    call bad('b_hardening', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&material name = ''b'', E = 1e9, nu = 0.3, rho = 1, sigma_y = 1, hardening = -1 /'], &
      [character(len=100) :: ':5: &material #2: hardening = -1: out of range'])
    call bad('b_cs', [character(len=100) :: run_ok, grid_ok, &
      '&material name = ''a'', E = 1e9, nu = 0.3, rho = 1, sigma_y = 1', &
      ' rate_law = ''cowper_symonds'', cs_d = 0, cs_q = -5 /', body_ok], &
      [character(len=100) :: ':4: &material #1: cs_d = 0: out of range', &
      ':4: &material #1: cs_q = -5: out of range'])
    call bad('b_rate_law', [character(len=100) :: run_ok, grid_ok, &
      '&material name = ''a'', E = 1e9, nu = 0.3, rho = 1, sigma_y = 1', &
      ' rate_law = ''johnson_cook'' /', body_ok], [character(len=100) :: &
      ':4: &material #1: rate_law = ''johnson_cook'': not an allowed value', &
      '''none'', ''cowper_symonds'''])
    call bad('b_name_missing', [character(len=100) :: run_ok, grid_ok, &
      '&material E = 1e9, nu = 0.3, rho = 1, sigma_y = 1 /', body_ok], &
      [character(len=100) :: ':3: &material #1: name: missing (required)'])
    call bad('b_name_long', [character(len=100) :: run_ok, grid_ok, &
      '&material E = 1e9, nu = 0.3, rho = 1, sigma_y = 1', ' name = '''// &
      'abcdefghijklmnopqrstuvwxyzabcdefghijklmnopqrstuvwxyzabcdefghijklmnopqrstuvwxyz'' /', &
      body_ok], [character(len=100) :: ':4: &material #1: name = ''abcdefghij', &
      'too long (78 characters)'])
    call bad('b_shape', [character(len=100) :: run_ok, grid_ok, mat_ok, &
      '&body shape = ''tubes'' /'], [character(len=100) :: &
      ':4: &body #1: shape = ''tubes'': not an allowed value', '''ring'', ''rect'', ''tube'''])
    call bad('b_n_thick', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&body r_inner = 1, r_outer = 2, n_thick = 0 /'], [character(len=100) :: &
      ':5: &body #2: n_thick = 0: out of range', 'an integer from 1 to 256'])
    call bad('b_n_circ', [character(len=100) :: run_ok, grid_ok, mat_ok, &
      '&body r_inner = 0.01, r_outer = 0.02', ' n_circ = 2 /'], [character(len=100) :: &
      ':5: &body #1: n_circ = 2: out of range', '0 (particles about square) or an integer >= 3'])
    call bad('b_sector', [character(len=100) :: run_ok, grid_ok, mat_ok, &
      '&body r_inner = 1, r_outer = 2, sector = ''third'' /'], [character(len=100) :: &
      ':4: &body #1: sector = ''third'': not an allowed value', &
      '''full'', ''half'', ''quarter'''])
    call bad('b_rect_size', [character(len=100) :: run_ok, grid_ok, mat_ok, &
      '&body shape = ''rect'', n_x = 2, n_y = 2', ' size = 0.1, -0.1 /'], [character(len=100) :: &
      ':5: &body #1: size = 0.1, -0.1: out of range', '2 real numbers > 0 [m]'])
    call bad('b_rect_n_x', [character(len=100) :: run_ok, grid_ok, mat_ok, &
      '&body shape = ''rect'', size = 1, 1, n_x = 0, n_y = 2 /'], [character(len=100) :: &
      ':4: &body #1: n_x = 0: out of range'])
    call bad('b_wall_point', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall normal = 0, 1 /'], [character(len=100) :: ':5: &wall #1: point: missing (required)'])
    call bad('b_normal_zero', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall point = 0, 0', '  normal = 0, 0 /'], [character(len=100) :: &
      ':6: &wall #1: normal = 0, 0: zero vector'])
    call bad('b_contact', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall point = 0, 0, normal = 1, 0, contact = ''glue'' /'], [character(len=100) :: &
      ':5: &wall #1: contact = ''glue'': not an allowed value', &
      '''frictionless'', ''coulomb'', ''stick'', ''slip'''])
    call bad('b_friction', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall point = 0, 0, normal = 1, 0, contact = ''coulomb''', ' friction = -0.1 /'], &
      [character(len=100) :: ':6: &wall #1: friction = -0.1: out of range'])
    call bad('b_ramp', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall point = 0, 0, normal = 1, 0, ramp = -1 /'], [character(len=100) :: &
      ':5: &wall #1: ramp = -1: out of range'])
    call bad('b_motion_negative', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall point = 0, 0, normal = 1, 0', ' motion_t = -1e-6, 0', ' motion_f = 1, 1 /'], &
      [character(len=100) :: &
      ':6: &wall #1: motion_t = -1e-6, 0: motion_t(1) = -1.0e-6 is negative'])
    call bad('b_motion_gap', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall point = 0, 0, normal = 1, 0', ' motion_t(1) = 0', ' motion_t(3) = 1', &
      ' motion_f = 1, 1, 1 /'], [character(len=100) :: &
      ':7: &wall #1: motion_t(3) = 1 (so motion_t = 0.0, (none), 1.0): motion_t(2) not given'])
    call bad('b_motion_null', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall point = 0, 0, normal = 1, 0', ' motion_t = 0, , 1', ' motion_f = 1, 1, 1 /'], &
      [character(len=100) :: ':6: &wall #1: motion_t = 0, , 1 (so motion_t = 0.0, (none), '// &
      '1.0): motion_t(2) not given'])
    call bad('b_motion_nan', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&wall point = 0, 0, normal = 1, 0', ' motion_t = 0, 1', ' motion_f = 0, nan /'], &
      [character(len=100) :: ':7: &wall #1: motion_f = 0, nan: motion_f(2) is not a finite'])
    call bad('b_suggest_variable', [character(len=100) :: run_ok, grid_ok, mat_ok, &
      '&body r_iner = 1, r_outer = 2 /'], [character(len=100) :: &
      ':4: &body #1: r_iner = 1: unknown variable (did you mean ''r_inner''?)'])
    call bad('b_subscript', [character(len=100) :: run_ok, '&grid h = 1', ' lower(3) = 1 /', &
      mat_ok, body_ok], [character(len=100) :: &
      ':3: &grid: lower(3) = 1: subscript out of range; allowed: lower(1) to lower(2)'])
    call bad('b_open_quote', [character(len=100) :: '&run t_end = 1', ' title = ''abc', '/', &
      grid_ok, mat_ok, body_ok], [character(len=100) :: ':2: &run: text value ''abc'// &
      ' is not closed on this line'])
    call bad('b_stray', [character(len=100) :: run_ok, '&grid h', '/', mat_ok, body_ok], &
      [character(len=100) :: ':2: &grid: unexpected text ''h'' (expected <name> = <value>)'])
    call bad('b_probe_unknown', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&probe point = 0, 0, radius = 1 /'], [character(len=100) :: &
      ':5: &probe #1: radius = 1: unknown variable; allowed: point'])
    call bad('b_unknown_group', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok, &
      '&materials name = ''x'' /'], [character(len=100) :: &
      ':5: &materials: unknown group (did you mean ''material''?)'])
    call bad('b_int_overflow', [character(len=100) :: run_ok, grid_ok, mat_ok, &
      '&body r_inner = 1, r_outer = 2, n_circ = 99999999999 /'], [character(len=100) :: &
      ':4: &body #1: n_circ = 99999999999: ''99999999999'' is not an integer (or is too large)'])
    call check(n_bad_inline >= 25, 'at least 25 inline bad cases ('//itoa(n_bad_inline)//')')
  end subroutine test_bad_inline

  !> Many mistakes in one file: all are reported, one line each, sorted by line.
  subroutine test_several_at_once()
    type(config_t) :: c
    integer :: stat, k, p, last
    character(len=:), allocatable :: msg, f
    character(len=70), parameter :: want(7) = [character(len=70) :: &
      'several.nml:2: &run: cfl = -1: out of range', &
      'several.nml:3: &solver: basis = ''gimp'': not an allowed value', &
      'several.nml:4: &grid: h = -1: out of range', &
      'several.nml:5: &material #1: E = 0: out of range', &
      'several.nml:6: &body #1: r_inner = 0.02: not below r_outer = 0.01', &
      'several.nml:7: &wall #1: normal = 1, 1: not of unit length', &
      'several.nml:8: &probe #1: point = 1: needs 2 values']
    call begin_test('several errors at once')
    f = write_case('several', [character(len=100) :: '! several mistakes', &
      '&run t_end = 1, cfl = -1 /', '&solver basis = ''gimp'' /', '&grid h = -1 /', &
      '&material name = ''a'', E = 0, nu = 0.3, rho = 1, sigma_y = 1 /', &
      '&body r_inner = 0.02, r_outer = 0.01 /', '&wall point = 0, 0, normal = 1, 1 /', &
      '&probe point = 1 /'])
    call read_config(f, c, stat, msg)
    call check(stat == EXIT_INPUT, 'several errors: stat = EXIT_INPUT')
    call check(count_lines(msg) == size(want), 'several errors: '//itoa(size(want))// &
      ' lines, got '//itoa(count_lines(msg)))
    last = 0
    do k = 1, size(want)
      p = index(msg, trim(want(k)))
      call check(p > 0, 'several errors: reports '//trim(want(k)))
      call check(p > last, 'several errors: in line order: '//trim(want(k)))
      last = p
    end do
  end subroutine test_several_at_once

  !> Every file in tests/bad_inputs/ gives EXIT_INPUT and contains each `! expect:` text.
  subroutine test_bad_files()
    type(config_t) :: c
    integer :: k, j, stat
    character(len=:), allocatable :: msg, path, text, line
    character(len=*), parameter :: tag = '! expect: '
    integer :: n_expect, p0, p1
    call begin_test('bad inputs (tests/bad_inputs)')
    do k = 1, size(bad_files)
      path = 'tests/bad_inputs/'//trim(bad_files(k))//'.nml'
      text = file_text(path)
      call check(len(text) > 0, path//' exists and is not empty')
      call read_config(path, c, stat, msg)
      call check(stat == EXIT_INPUT, path//': stat = EXIT_INPUT (got '//itoa(stat)//')')
      n_expect = 0
      p0 = 1
      do while (p0 <= len(text))
        p1 = index(text(p0:), new_line('a'))
        if (p1 == 0) p1 = len(text) - p0 + 2
        line = text(p0:p0+p1-2)
        p0 = p0 + p1
        if (len(line) <= len(tag)) cycle
        if (line(1:len(tag)) /= tag) cycle
        n_expect = n_expect + 1
        j = index(msg, line(len(tag)+1:))
        call check(j > 0, path//': message contains "'//line(len(tag)+1:)//'"; got: '//msg)
      end do
      call check(n_expect > 0, path//' has at least one "! expect:" line')
    end do
  end subroutine test_bad_files

  !> A missing file is an I/O error; so is writing into a folder that does not exist.
  subroutine test_io_errors()
    type(config_t) :: c
    integer :: stat
    character(len=:), allocatable :: msg
    call begin_test('I/O errors')
    call read_config(dir//'/no_such_file.nml', c, stat, msg)
    call check(stat == EXIT_IO, 'missing file: stat = EXIT_IO')
    call check(index(msg, 'no_such_file.nml: cannot open the input file') > 0, &
      'missing file: message names the file: '//msg)
    call default_config(c)
    call write_config(c, dir//'/no/such/folder/x.nml', stat, msg)
    call check(stat == EXIT_IO, 'unwritable path: stat = EXIT_IO')
    call check(index(msg, 'x.nml') > 0, 'unwritable path: message names the file: '//msg)
  end subroutine test_io_errors

  !> Files without a final newline, with CRLF line ends or tabs read like any other; a number
  !! too large for a double is reported (also under FP overflow traps), never a crash.
  subroutine test_file_formats()
    type(config_t) :: c, ref
    integer :: stat, u, ios
    character(len=:), allocatable :: msg, f, cr, body
    character(len=256) :: iomsg
    call begin_test('file formats')
    cr = achar(13)//achar(10)
    body = run_ok//achar(10)//grid_ok//achar(10)//mat_ok//achar(10)//achar(9)//body_ok
    f = write_case('ref_format', [character(len=100) :: run_ok, grid_ok, mat_ok, body_ok])
    call read_config(f, ref, stat, msg)
    call check(stat == 0, 'reference reads: '//msg)
    f = dir//'/no_newline.nml'
    open(newunit=u, file=f, access='stream', form='unformatted', status='replace', &
         action='write', iostat=ios, iomsg=iomsg)
    call check(ios == 0, 'open '//f//': '//trim(iomsg))
    write(u, iostat=ios, iomsg=iomsg) body                ! no newline after the last '/'
    close(u, iostat=ios, iomsg=iomsg)
    call read_config(f, c, stat, msg)
    call check(stat == 0, 'a last line without newline reads: '//msg)
    if (stat == 0) call check(c%bodies(1)%r_outer == ref%bodies(1)%r_outer, 'same values')
    f = dir//'/crlf.nml'
    open(newunit=u, file=f, access='stream', form='unformatted', status='replace', &
         action='write', iostat=ios, iomsg=iomsg)
    write(u, iostat=ios, iomsg=iomsg) run_ok//cr//grid_ok//cr//mat_ok//cr//body_ok//cr
    close(u, iostat=ios, iomsg=iomsg)
    call read_config(f, c, stat, msg)
    call check(stat == 0, 'CRLF line ends read: '//msg)
    if (stat == 0) call check(c%materials(1)%E == ref%materials(1)%E, 'same values (CRLF)')
    call bad('b_overflow', [character(len=100) :: '&run t_end = 1e-3', ' depth = 1e400 /', &
      grid_ok, mat_ok, body_ok], [character(len=100) :: &
      ':2: &run: depth = 1e400: not a finite number'])
    call read_config(dir, c, stat, msg)
    call check(stat == EXIT_IO, 'a folder: stat = EXIT_IO')
    call check(index(msg, 'is a folder, not a namelist file') > 0, 'a folder: message: '//msg)
  end subroutine test_file_formats

  ! ---------------------------------------------------------------------- helpers

  !> Write a bad case, read it, check EXIT_INPUT and that every expected text (prefixed
  !! with the file name when it starts with ':') is in the message.
  subroutine bad(name, lines, expects)
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: lines(:), expects(:)
    type(config_t) :: c
    integer :: stat, k
    character(len=:), allocatable :: msg, f, e
    n_bad_inline = n_bad_inline + 1
    f = write_case(name, lines)
    call read_config(f, c, stat, msg)
    call check(stat == EXIT_INPUT, name//': stat = EXIT_INPUT (got '//itoa(stat)//')')
    do k = 1, size(expects)
      e = trim(expects(k))
      if (e(1:1) == ':') e = name//'.nml'//e
      call check(index(msg, e) > 0, name//': message contains "'//e//'"; got: '//msg)
    end do
  end subroutine bad

  !> Write lines to <scratch>/<name>.nml and return the path.
  function write_case(name, lines) result(f)
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: lines(:)
    character(len=:), allocatable :: f
    integer :: u, ios, k
    character(len=256) :: iomsg
    f = dir//'/'//name//'.nml'
    open(newunit=u, file=f, status='replace', action='write', iostat=ios, iomsg=iomsg)
    call check(ios == 0, 'open '//f//': '//trim(iomsg))
    if (ios /= 0) return
    do k = 1, size(lines)
      write(u, '(a)', iostat=ios, iomsg=iomsg) trim(lines(k))
    end do
    close(u, iostat=ios, iomsg=iomsg)
  end function write_case

  !> Whole text of a file, lines joined by new_line ('' if it cannot be read).
  function file_text(f) result(text)
    character(len=*), intent(in) :: f
    character(len=:), allocatable :: text
    character(len=4096) :: line
    integer :: u, ios
    character(len=256) :: iomsg
    text = ''
    open(newunit=u, file=f, status='old', action='read', iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios, iomsg=iomsg) line
      if (ios /= 0) exit
      text = text//trim(line)//new_line('a')
    end do
    close(u, iostat=ios, iomsg=iomsg)
  end function file_text

  pure integer function count_lines(s) result(n)
    character(len=*), intent(in) :: s
    integer :: k
    n = 0
    if (len_trim(s) == 0) return
    n = 1
    do k = 1, len(s)
      if (s(k:k) == new_line('a')) n = n + 1
    end do
  end function count_lines

  pure function group_of(k) result(g)
    integer, intent(in) :: k
    character(len=8) :: g
    character(len=8), parameter :: names(7) = [character(len=8) :: 'run', 'solver', 'grid', &
      'material', 'body', 'wall', 'probe']
    g = names(k)
  end function group_of

  !> x with 18 significant digits (more than enough to be exact).
  function e17(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    character(len=128) :: msg
    integer :: ios
    write(buf, '(es25.17e3)', iostat=ios, iomsg=msg) x
    s = trim(adjustl(buf))
  end function e17

  !> Names of the components in which two configs differ ('' when identical); cfg%file
  !! differs by construction and is not compared.
  function config_diff(a, b) result(d)
    type(config_t), intent(in) :: a, b
    character(len=:), allocatable :: d
    integer :: k
    d = ''
    call cmp(d, a%run%title == b%run%title, 'run%title')
    call cmp(d, a%run%output_dir == b%run%output_dir, 'run%output_dir')
    call cmp(d, a%run%t_end == b%run%t_end, 'run%t_end')
    call cmp(d, a%run%cfl == b%run%cfl, 'run%cfl')
    call cmp(d, a%run%dt == b%run%dt, 'run%dt')
    call cmp(d, a%run%history_every == b%run%history_every, 'run%history_every')
    call cmp(d, a%run%snapshot_every == b%run%snapshot_every, 'run%snapshot_every')
    call cmp(d, a%run%checkpoint_every == b%run%checkpoint_every, 'run%checkpoint_every')
    call cmp(d, a%run%depth == b%run%depth, 'run%depth')
    call cmp(d, all(a%run%gravity == b%run%gravity), 'run%gravity')
    call cmp(d, a%run%threads == b%run%threads, 'run%threads')
    call cmp(d, a%solver%basis == b%solver%basis, 'solver%basis')
    call cmp(d, a%solver%scheme == b%solver%scheme, 'solver%scheme')
    call cmp(d, a%solver%plane == b%solver%plane, 'solver%plane')
    call cmp(d, a%solver%basis_id == b%solver%basis_id, 'solver%basis_id')
    call cmp(d, a%solver%scheme_id == b%solver%scheme_id, 'solver%scheme_id')
    call cmp(d, a%solver%plane_id == b%solver%plane_id, 'solver%plane_id')
    call cmp(d, a%solver%flip == b%solver%flip, 'solver%flip')
    call cmp(d, a%solver%mass_scale == b%solver%mass_scale, 'solver%mass_scale')
    call cmp(d, a%solver%damping == b%solver%damping, 'solver%damping')
    call cmp(d, a%solver%deterministic .eqv. b%solver%deterministic, 'solver%deterministic')
    call cmp(d, a%grid%h == b%grid%h, 'grid%h')
    call cmp(d, all(a%grid%lower == b%grid%lower), 'grid%lower')
    call cmp(d, all(a%grid%upper == b%grid%upper), 'grid%upper')
    call cmp(d, a%grid%fitted .eqv. b%grid%fitted, 'grid%fitted')
    call cmp(d, size(a%materials) == size(b%materials), 'size(materials)')
    call cmp(d, size(a%bodies) == size(b%bodies), 'size(bodies)')
    call cmp(d, size(a%walls) == size(b%walls), 'size(walls)')
    call cmp(d, size(a%probes) == size(b%probes), 'size(probes)')
    if (len(d) > 0) return
    do k = 1, size(a%materials)
      associate (x => a%materials(k), y => b%materials(k))
        call cmp(d, x%name == y%name, 'materials%name')
        call cmp(d, x%model == y%model, 'materials%model')
        call cmp(d, x%rate_law == y%rate_law, 'materials%rate_law')
        call cmp(d, x%model_id == y%model_id, 'materials%model_id')
        call cmp(d, x%rate_law_id == y%rate_law_id, 'materials%rate_law_id')
        call cmp(d, x%E == y%E, 'materials%E')
        call cmp(d, x%nu == y%nu, 'materials%nu')
        call cmp(d, x%rho == y%rho, 'materials%rho')
        call cmp(d, x%sigma_y == y%sigma_y, 'materials%sigma_y')
        call cmp(d, x%hardening == y%hardening, 'materials%hardening')
        call cmp(d, x%cs_d == y%cs_d, 'materials%cs_d')
        call cmp(d, x%cs_q == y%cs_q, 'materials%cs_q')
        call cmp(d, x%sigma_p == y%sigma_p .and. x%nu_plastic == y%nu_plastic .and. &
          x%foam_alpha == y%foam_alpha .and. x%foam_gamma == y%foam_gamma .and. &
          x%foam_alpha2 == y%foam_alpha2 .and. x%foam_beta == y%foam_beta .and. &
          x%eps_d == y%eps_d, 'materials%(foam law)')
        call cmp(d, x%n_curve == y%n_curve .and. all(x%curve_strain == y%curve_strain) .and. &
          all(x%curve_stress == y%curve_stress), 'materials%(foam curve)')
      end associate
    end do
    do k = 1, size(a%bodies)
      associate (x => a%bodies(k), y => b%bodies(k))
        call cmp(d, x%shape == y%shape, 'bodies%shape')
        call cmp(d, x%material == y%material, 'bodies%material')
        call cmp(d, x%sector == y%sector, 'bodies%sector')
        call cmp(d, x%shape_id == y%shape_id, 'bodies%shape_id')
        call cmp(d, x%material_id == y%material_id, 'bodies%material_id')
        call cmp(d, x%sector_id == y%sector_id, 'bodies%sector_id')
        call cmp(d, all(x%center == y%center), 'bodies%center')
        call cmp(d, x%r_inner == y%r_inner, 'bodies%r_inner')
        call cmp(d, x%r_outer == y%r_outer, 'bodies%r_outer')
        call cmp(d, x%n_thick == y%n_thick, 'bodies%n_thick')
        call cmp(d, x%n_circ == y%n_circ, 'bodies%n_circ')
        call cmp(d, all(x%size == y%size), 'bodies%size')
        call cmp(d, x%n_x == y%n_x, 'bodies%n_x')
        call cmp(d, x%n_y == y%n_y, 'bodies%n_y')
        call cmp(d, all(x%velocity == y%velocity), 'bodies%velocity')
      end associate
    end do
    do k = 1, size(a%walls)
      associate (x => a%walls(k), y => b%walls(k))
        call cmp(d, all(x%point == y%point), 'walls%point')
        call cmp(d, all(x%normal == y%normal), 'walls%normal')
        call cmp(d, x%contact == y%contact, 'walls%contact')
        call cmp(d, x%contact_id == y%contact_id, 'walls%contact_id')
        call cmp(d, x%friction == y%friction, 'walls%friction')
        call cmp(d, all(x%velocity == y%velocity), 'walls%velocity')
        call cmp(d, x%ramp == y%ramp, 'walls%ramp')
        call cmp(d, x%n_motion == y%n_motion, 'walls%n_motion')
        call cmp(d, all(x%motion_t == y%motion_t), 'walls%motion_t')
        call cmp(d, all(x%motion_f == y%motion_f), 'walls%motion_f')
        call cmp(d, x%mirror .eqv. y%mirror, 'walls%mirror')
        call cmp(d, x%mass == y%mass, 'walls%mass')
        call cmp(d, x%stroke == y%stroke, 'walls%stroke')
        call cmp(d, x%penalty == y%penalty, 'walls%penalty')
      end associate
    end do
    do k = 1, size(a%probes)
      call cmp(d, all(a%probes(k)%point == b%probes(k)%point), 'probes%point')
    end do
  end function config_diff

  !> Append what to the list d when not same.
  subroutine cmp(d, same, what)
    character(len=:), allocatable, intent(inout) :: d
    logical, intent(in) :: same
    character(len=*), intent(in) :: what
    if (.not. same) d = d//' '//what
  end subroutine cmp
end program test_config
