!> The input variables: one row per namelist variable, from which the reader, the range checks,
!! the allowed-value messages, the resolved echo (input.nml) and the docs check
!! (tests/test_docs_input.py) are all derived.
! SPDX-License-Identifier: MIT
!
! A row gives: group, name, kind (r real, i integer, l logical, c text, e one of a list of
! names), number of values, the value the reader starts from (r0/i0/c0: the default, or a
! "not given" sentinel that the group's validation turns into the default), the admissible
! range (lo/hi, open or closed, required), the text of "allowed:" in messages (units in
! brackets, default in parentheses; for kind e it is made from the list of names), the
! comment of the echo (meaning and unit; % stands for the list of names), which body shape the
! variable belongs to, and how the echo recognises a required value that was not set.
module mpm_config_table
  use mpm_kinds, only: wp
  use mpm_constants, only: name_len, path_len, max_table, basis_names, scheme_names, &
                           plane_names, model_names, rate_law_names, shape_names, sector_names, &
                           contact_names, flow_stress_names, volumetric_names, max_vertices, &
                           max_cells
  use mpm_config_types, only: config_t, unset_real, iunset
  use mpm_config_text, only: enum_text, join_list, lower
  implicit none
  private
  public :: var_spec_t, specs, n_specs, n_groups, group_names, group_repeatable
  public :: group_id, spec_index, group_specs, var_list, var_names, allowed_text, enum_names, &
            echo_comment, unset_note, field_t, bind_fields

  integer, parameter :: n_groups = 8
  character(len=*), parameter :: group_names(n_groups) = [character(len=8) :: &
    'run', 'solver', 'grid', 'material', 'body', 'wall', 'probe', 'contact']
  logical, parameter :: group_repeatable(n_groups) = &
    [.false., .false., .false., .true., .true., .true., .true., .true.]

  real(wp), parameter :: big = huge(1.0_wp)

  !> One namelist variable.
  type :: var_spec_t
    character(len=8) :: group = ''
    character(len=16) :: name = ''
    character(len=1) :: kind = 'r'          !! r, i, l, c, e
    integer :: n = 1                        !! number of values
    real(wp) :: r0 = 0.0_wp                 !! starting value of a real
    integer :: i0 = 0                       !! starting value of an integer
    character(len=16) :: c0 = ''            !! default text (kind c, e)
    logical :: l0 = .false.                 !! default of a logical
    logical :: c_blank = .false.            !! the reader starts from '' (given or not?)
    logical :: required = .false.
    logical :: whole = .false.              !! real values that must be whole numbers (echo
                                            !! writes them as integers)
    real(wp) :: lo = -big, hi = big         !! range
    logical :: lo_open = .false., hi_open = .false.  !! lo < x (not <=), x < hi (not <=)
    integer :: max_len = name_len           !! longest text
    character(len=40) :: only = ''          !! the body shapes the variable belongs to
                                            !! (names separated by blanks; '' = every shape),
                                            !! or for &material the model ('foam')
    character(len=4) :: unset = ''          !! echo: not set when neg (-1), huge, empty, zero
    character(len=56) :: unset_note = ''    !! echo comment when not set ('' when required:
                                            !! 'required: ' and the comment, unset_note())
    character(len=160) :: allowed = ''      !! "allowed:" text of messages ('' for kind e)
    character(len=48) :: comment = ''       !! echo comment: meaning [unit]; % = the names
    logical :: own = .false.                !! checked and stored by the group's own rules
    logical :: quiet = .false.              !! left out of the echo while at its default (r0, l0)
  end type var_spec_t

  !> Where the value of a row lives in a config_t record (bind_fields): the pointer of the
  !! row's kind (a text and a code for kind e; iv for whole numbers).
  type :: field_t
    real(wp), pointer :: x => null(), v(:) => null()
    integer, pointer :: i => null(), iv(:) => null()
    logical, pointer :: l => null()
    character(len=:), pointer :: c => null()
  end type field_t

  character(len=*), parameter :: s0 = 'a real number >= 0 [s] (default 0)'
  character(len=*), parameter :: v0 = '2 finite real numbers [m/s] (default 0, 0)'
  character(len=*), parameter :: lu = '2 real numbers [m] each for lower and upper, lower '// &
    '< upper in both components, both given or neither (then fitted)'

  type(var_spec_t), parameter :: specs(*) = [ &
    ! ---------------------------------------------------------------------------- &run
    var_spec_t('run', 'title', 'c', unset='emp', unset_note='default: the file name stem', &
      allowed='text of at most 64 characters (default: the file name stem)', &
      comment='label of the case'), &
    var_spec_t('run', 'output_dir', 'c', max_len=path_len, unset='emp', &
      unset_note='default: out/<title>', &
      allowed='a folder path of at most 512 characters (default: out/<title>)', &
      comment='folder for all outputs'), &
    var_spec_t('run', 't_end', r0=big, lo=0.0_wp, lo_open=.true., unset='neg', &
      unset_note='default: when every moving wall has reached its stroke', &
      allowed='a real number > 0 [s] (required unless every moving &wall has a stroke)', &
      comment='simulated time [s]'), &
    var_spec_t('run', 'cfl', r0=0.0_wp, lo=0.0_wp, hi=2.0_wp, &
      allowed='a real number with 0 <= cfl <= 2 (default 0: automatic; --check warns above '// &
      'the stability study''s limit)', comment='dt = cfl h / (c_d + max speed) [-]'), &
    var_spec_t('run', 'dt', lo=0.0_wp, allowed='a real number >= 0 [s] (0 = from cfl; '// &
      'default 0)', comment='fixed time step if > 0 [s]'), &
    var_spec_t('run', 'history_every', lo=0.0_wp, allowed=s0, &
      comment='history.csv interval [s]'), &
    var_spec_t('run', 'snapshot_every', lo=0.0_wp, allowed=s0, &
      comment='snapshot interval [s]'), &
    var_spec_t('run', 'checkpoint_every', lo=0.0_wp, allowed=s0, &
      comment='wall-clock checkpoint interval [s]'), &
    var_spec_t('run', 'depth', r0=1.0_wp, lo=0.0_wp, lo_open=.true., &
      allowed='a real number > 0 [m] (default 1.0)', comment='out-of-plane length [m]'), &
    var_spec_t('run', 'gravity', n=2, allowed='2 finite real numbers [m/s^2] (default 0, 0)', &
      comment='body acceleration [m/s^2]'), &
    var_spec_t('run', 'threads', 'i', lo=0.0_wp, &
      allowed='an integer >= 0 (0 = one per core that other work does not keep busy)', &
      comment='OpenMP threads (0 = runtime default)'), &
    var_spec_t('run', 'mirror_images', 'l', l0=.true., allowed='.true. or .false. (default '// &
      '.true.)', comment='write the mirror images of a sector', quiet=.true.), &
    var_spec_t('run', 'end_at_release', 'l', allowed='.true. or .false. '// &
      '(default .false.)', comment='end the run when its contact is over', quiet=.true.), &
    var_spec_t('run', 'check_units', 'l', l0=.true., allowed='.true. or .false. (default '// &
      '.true.: refuse values that are usually a wrong unit)', &
      comment='refuse values in a likely wrong unit', quiet=.true.), &
    ! ---------------------------------------------------------------------------- &solver
    var_spec_t('solver', 'basis', 'e', c0='cpdi2', comment='% [-]'), &
    var_spec_t('solver', 'scheme', 'e', c0='musl', comment='% [-]'), &
    var_spec_t('solver', 'flip', r0=1.0_wp, lo=0.0_wp, hi=1.0_wp, &
      allowed='a real number with 0 <= flip <= 1 (default 1.0)', &
      comment='FLIP fraction (1 FLIP, 0 PIC) [-]'), &
    var_spec_t('solver', 'plane', 'e', c0='strain', comment='% [-]'), &
    var_spec_t('solver', 'volumetric', 'e', c0='standard', comment='% (fbar: anti-locking) [-]'), &
    var_spec_t('solver', 'mass_scale', r0=1.0_wp, lo=1.0_wp, &
      allowed='a real number >= 1 (default 1.0)', comment='density multiplier [-]'), &
    var_spec_t('solver', 'damping', lo=0.0_wp, allowed='a real number >= 0 [1/s] (default 0)', &
      comment='mass-proportional damping [1/s]'), &
    var_spec_t('solver', 'deterministic', 'l', allowed='.true. or .false. (default .false.)', &
      comment='results independent of the thread count'), &
    ! ---------------------------------------------------------------------------- &grid
    var_spec_t('grid', 'h', r0=big, required=.true., lo=0.0_wp, lo_open=.true., unset='neg', &
      allowed='a real number > 0 [m] (required)', comment='cell size [m]'), &
    var_spec_t('grid', 'lower', n=2, r0=big, allowed=lu, comment='lower domain corner [m]', &
      own=.true.), &
    var_spec_t('grid', 'upper', n=2, r0=big, allowed=lu, comment='upper domain corner [m]', &
      own=.true.), &
    ! ---------------------------------------------------------------------------- &material
    var_spec_t('material', 'name', 'c', required=.true., unset='emp', &
      allowed='text of 1 to 64 characters, unique among the &material groups (required)', &
      comment='label used by &body'), &
    var_spec_t('material', 'model', 'e', c0='j2', comment='%'), &
    var_spec_t('material', 'E', r0=big, required=.true., lo=0.0_wp, lo_open=.true., &
      unset='neg', allowed='a real number > 0 [Pa] (required)', comment='Young''s modulus [Pa]'), &
    var_spec_t('material', 'nu', r0=big, required=.true., lo=0.0_wp, hi=0.5_wp, &
      hi_open=.true., unset='neg', &
      allowed='a real number with 0 <= nu < 0.5 (required)', comment='Poisson''s ratio [-]'), &
    var_spec_t('material', 'rho', r0=big, required=.true., lo=0.0_wp, lo_open=.true., &
      unset='neg', allowed='a real number > 0 [kg/m^3] (required)', comment='density [kg/m^3]'), &
    var_spec_t('material', 'sigma_y', own=.true., r0=big, lo=0.0_wp, lo_open=.true., unset='neg', &
      unset_note='required for model = ''j2'': initial yield stress [Pa]', &
      allowed='a real number > 0 [Pa] (required for model = ''j2'')', &
      comment='initial yield stress [Pa]'), &
    var_spec_t('material', 'hardening', lo=0.0_wp, allowed='a real number >= 0 [Pa] '// &
      '(default 0)', comment='linear isotropic hardening modulus [Pa]'), &
    var_spec_t('material', 'voce_q', lo=0.0_wp, quiet=.true., allowed='a real number >= 0 '// &
      '[Pa] (default 0: no saturation term)', comment='Voce saturation stress Q [Pa]'), &
    var_spec_t('material', 'voce_b', r0=10.0_wp, lo=0.0_wp, lo_open=.true., quiet=.true., &
      allowed='a real number > 0 (default 10)', comment='Voce saturation rate b [-]'), &
    var_spec_t('material', 'rate_law', 'e', c0='none', comment='%'), &
    var_spec_t('material', 'cs_d', r0=40.4_wp, lo=0.0_wp, lo_open=.true., &
      allowed='a real number > 0 [1/s] (default 40.4)', comment='Cowper-Symonds D [1/s]'), &
    var_spec_t('material', 'cs_q', r0=5.0_wp, lo=0.0_wp, lo_open=.true., &
      allowed='a real number > 0 (default 5)', comment='Cowper-Symonds q [-]'), &
    var_spec_t('material', 'flow_stress', 'e', c0='linear', comment='%'), &
    var_spec_t('material', 'jc_b', lo=0.0_wp, allowed='a real number >= 0 [Pa] (default 0)', &
      comment='Johnson-Cook B [Pa]'), &
    var_spec_t('material', 'jc_n', r0=1.0_wp, lo=0.0_wp, lo_open=.true., hi=1.0_wp, &
      allowed='a real number with 0 < jc_n <= 1 (default 1)', comment='Johnson-Cook n [-]'), &
    var_spec_t('material', 'jc_c', lo=0.0_wp, allowed='a real number >= 0 (default 0)', &
      comment='Johnson-Cook C [-]'), &
    var_spec_t('material', 'jc_rate0', r0=1.0_wp, lo=0.0_wp, lo_open=.true., &
      allowed='a real number > 0 [1/s] (default 1)', &
      comment='Johnson-Cook reference strain rate [1/s]'), &
    var_spec_t('material', 'sigma_p', own=.true., r0=big, lo=0.0_wp, lo_open=.true., &
      only='foam', unset='neg', allowed='a real number > 0 [Pa] (required for model = '// &
      '''foam'' without curve_strain, curve_stress)', comment='foam plateau stress [Pa]'), &
    var_spec_t('material', 'nu_plastic', own=.true., r0=big, lo=-1.0_wp, lo_open=.true., &
      hi=0.5_wp, hi_open=.true., only='foam', allowed='a real number with -1 < nu_plastic '// &
      '< 0.5, not with foam_alpha (default 0: alpha = 2.12)', &
      comment='foam plastic Poisson''s ratio [-]'), &
    var_spec_t('material', 'foam_alpha', own=.true., r0=big, lo=0.0_wp, lo_open=.true., &
      only='foam', unset='neg', unset_note='default: from nu_plastic', allowed='a real '// &
      'number > 0, not with nu_plastic (default: from nu_plastic)', &
      comment='foam yield surface shape alpha [-]'), &
    var_spec_t('material', 'foam_gamma', lo=0.0_wp, only='foam', allowed='a real number '// &
      '>= 0 [Pa], not with a curve (default 0)', comment='foam hardening gamma [Pa]'), &
    var_spec_t('material', 'foam_alpha2', lo=0.0_wp, only='foam', allowed='a real number '// &
      '>= 0 [Pa], not with a curve (default 0)', comment='foam densification alpha2 [Pa]'), &
    var_spec_t('material', 'foam_beta', r0=1.0_wp, lo=0.0_wp, lo_open=.true., only='foam', &
      allowed='a real number > 0, not with a curve (default 1)', &
      comment='foam densification exponent beta [-]'), &
    var_spec_t('material', 'eps_d', own=.true., r0=big, lo=0.0_wp, lo_open=.true., &
      only='foam', unset='neg', allowed='a real number > 0 (required for model = ''foam'' '// &
      'without curve_strain, curve_stress)', comment='foam densification strain [-]'), &
    var_spec_t('material', 'curve_strain', n=max_table, r0=big, own=.true., only='foam', &
      allowed='up to 64 plastic strains, the first 0, strictly increasing, as many as '// &
      'curve_stress (default none: the law)', comment='plastic strains [-]'), &
    var_spec_t('material', 'curve_stress', n=max_table, r0=big, own=.true., only='foam', &
      allowed='up to 64 yield stresses > 0 [Pa], not decreasing, as many as '// &
      'curve_strain (default none)', comment='uniaxial yield stresses [Pa]'), &
    ! ---------------------------------------------------------------------------- &body
    var_spec_t('body', 'shape', 'e', c0='ring', comment='%'), &
    var_spec_t('body', 'material', 'c', unset='emp', unset_note='default: the first material', &
      allowed='the name of a &material (default: the first material)', &
      comment='a &material name'), &
    var_spec_t('body', 'center', n=2, allowed='2 finite real numbers [m] (default 0, 0)', &
      comment='centre [m]'), &
    var_spec_t('body', 'r_inner', r0=big, required=.true., lo=0.0_wp, lo_open=.true., &
      only='ring', unset='neg', &
      allowed='a real number with 0 < r_inner < r_outer [m] (required for shape = ''ring'')', &
      comment='inner radius [m]'), &
    var_spec_t('body', 'r_outer', r0=big, required=.true., lo=0.0_wp, lo_open=.true., &
      only='ring disc', unset='neg', &
      allowed='a real number > r_inner [m] (required for shape = ''ring'' and ''disc'')', &
      comment='outer radius [m]'), &
    var_spec_t('body', 'n_thick', 'i', i0=iunset, lo=1.0_wp, hi=256.0_wp, &
      only='ring tube honeycomb walls disc', &
      allowed='an integer from 1 to 256, even where three walls meet at an angle (default 16)', &
      comment='particles through the wall (disc: radius)'), &
    var_spec_t('body', 'n_circ', 'i', i0=iunset, only='ring', own=.true., &
      allowed='0 (particles about square) or an integer >= 3, divisible by 2 for sector = '// &
      '''half'' and by 4 for ''quarter'' (default 0)', &
      comment='particles around the whole ring (0 = auto)'), &
    var_spec_t('body', 'sector', 'e', c0='full', c_blank=.true., only='ring tube walls disc', &
      comment='%'), &
    var_spec_t('body', 'self_contact', 'l', only='ring tube honeycomb walls', &
      allowed='.true. or .false. (default '// &
      '.false.); .true. needs sector = ''full'' or ''half''', comment='walls meet, never weld'), &
    var_spec_t('body', 'size', n=2, r0=big, required=.true., lo=0.0_wp, lo_open=.true., &
      only='rect', unset='neg', allowed='2 real numbers > 0 [m] (required for shape = ''rect'')', &
      comment='rectangle sides [m]'), &
    var_spec_t('body', 'n_x', 'i', i0=iunset, required=.true., lo=1.0_wp, only='rect', &
      unset='zero', &
      allowed='an integer >= 1 (required for shape = ''rect'')', comment='particles along x'), &
    var_spec_t('body', 'n_y', 'i', i0=iunset, required=.true., lo=1.0_wp, only='rect', &
      unset='zero', &
      allowed='an integer >= 1 (required for shape = ''rect'')', comment='particles along y'), &
    var_spec_t('body', 'vertices', n=2*max_vertices, r0=big, own=.true., only='tube', &
      allowed='3 to 64 points x, y [m] of the centreline polygon, counter-clockwise, '// &
      'finite (required for shape = ''tube'')', comment='centreline polygon x, y, ... [m]'), &
    var_spec_t('body', 'thickness', r0=big, required=.true., lo=0.0_wp, lo_open=.true., &
      only='tube honeycomb', unset='neg', allowed='a real number > 0 [m] (required for '// &
      'shape = ''tube'' and ''honeycomb'')', comment='wall thickness [m]'), &
    var_spec_t('body', 'corner_radius', lo=0.0_wp, only='tube', allowed='0 (sharp) or a '// &
      'real number >= thickness/2 [m] (default 0)', comment='corner radius, centreline [m]'), &
    var_spec_t('body', 'n_cells', own=.true., n=2, r0=0.0_wp, whole=.true., only='honeycomb', &
      unset='zero', allowed='2 whole numbers from 1 to 64: cells along x and y (required '// &
      'for shape = ''honeycomb'')', comment='cells along x and y'), &
    var_spec_t('body', 'cell_l', r0=big, required=.true., lo=0.0_wp, lo_open=.true., &
      only='honeycomb', unset='neg', allowed='a real number > 0 [m] (required for shape '// &
      '= ''honeycomb'')', comment='inclined wall length [m]'), &
    var_spec_t('body', 'cell_h', r0=big, required=.true., lo=0.0_wp, lo_open=.true., &
      only='honeycomb', unset='neg', allowed='a real number > 0 [m] (required for shape '// &
      '= ''honeycomb'')', comment='vertical wall length [m]'), &
    var_spec_t('body', 'cell_angle', r0=30.0_wp, lo=-80.0_wp, hi=80.0_wp, only='honeycomb', &
      allowed='a real number from -80 to 80 [degrees], not 0, with cell_h/2 + cell_l '// &
      'sin(angle) > thickness (default 30)', comment='inclined wall angle to x [deg]'), &
    var_spec_t('body', 'walls_file', 'c', max_len=path_len, required=.true., unset='emp', &
      only='walls', allowed='a CSV file (relative to the input file''s folder), one wall '// &
      'per line: x1, y1, x2, y2, thickness [m] (required for shape = ''walls'')', &
      comment='CSV of walls: x1, y1, x2, y2, t'), &
    var_spec_t('body', 'velocity', n=2, allowed=v0, comment='initial velocity [m/s]'), &
    ! ---------------------------------------------------------------------------- &wall
    var_spec_t('wall', 'point', n=2, r0=big, required=.true., unset='huge', &
      allowed='2 finite real numbers [m] (required)', &
      comment='a point on the plane at t = 0 [m]'), &
    var_spec_t('wall', 'normal', own=.true., n=2, r0=big, required=.true., unset='huge', &
      allowed='2 real numbers forming a unit vector, |normal| = 1 within 1e-6 (required)', &
      comment='unit normal into the material side [-]'), &
    var_spec_t('wall', 'contact', 'e', c0='frictionless', comment='%'), &
    var_spec_t('wall', 'friction', lo=0.0_wp, allowed='a real number >= 0, and > 0 only '// &
      'with contact = ''coulomb'' or ''bonded'' (default 0)', &
      comment='Coulomb coefficient [-]'), &
    var_spec_t('wall', 'velocity', n=2, allowed=v0, comment='prescribed velocity [m/s]'), &
    var_spec_t('wall', 'ramp', lo=0.0_wp, allowed='a real number >= 0 [s] (default 0)', &
      comment='smooth rise time of the velocity [s]'), &
    var_spec_t('wall', 'motion_t', n=max_table, r0=big, own=.true., &
      allowed='up to 64 times [s], >= 0 '// &
      'and strictly increasing, as many as motion_f (default none)', comment='times [s]'), &
    var_spec_t('wall', 'motion_f', n=max_table, r0=big, own=.true., &
      allowed='up to 64 finite factors, '// &
      'as many as motion_t (default none)', comment='factors on velocity [-]'), &
    var_spec_t('wall', 'mass', lo=0.0_wp, allowed='a real number >= 0 [kg] (0: prescribed '// &
      'motion; > 0: a free rigid body, for depth; default 0)', &
      comment='> 0: drop weight of this mass [kg]'), &
    var_spec_t('wall', 'stroke', lo=0.0_wp, allowed='a real number >= 0 [m] (0: none; '// &
      'default 0)', comment='> 0: eases to rest at this travel [m]'), &
    ! ---------------------------------------------------------------------------- &probe
    var_spec_t('probe', 'point', n=2, r0=big, required=.true., unset='huge', &
      allowed='2 finite real numbers [m] (required)', &
      comment='the particle nearest to it is recorded [m]'), &
    ! ---------------------------------------------------------------------------- &contact
    var_spec_t('contact', 'bodies', own=.true., n=2, r0=0.0_wp, lo=0.0_wp, whole=.true., &
      allowed='2 integers: two different bodies by their order in the file (1, 2, ...), '// &
      'or 0, 0 for every pair not named in another &contact (default 0, 0)', &
      comment='the two bodies (0, 0 = every other pair) [-]'), &
    var_spec_t('contact', 'law', 'e', c0='frictionless', comment='%'), &
    var_spec_t('contact', 'friction', lo=0.0_wp, allowed='a real number >= 0, and > 0 only '// &
      'with law = ''coulomb'' (default 0)', comment='Coulomb coefficient [-]')]
  integer, parameter :: n_specs = size(specs)   !! rows (counted, not written)

contains

  !> Index of a group name in group_names, 0 if unknown.
  pure integer function group_id(name)
    character(len=*), intent(in) :: name   !! group name, lower case
    group_id = findloc(group_names, name, 1)
  end function group_id

  !> Row of variable `name` (case-insensitive, as the file writes it) of a group, 0 if none.
  pure integer function spec_index(group, name) result(k)
    character(len=*), intent(in) :: group, name
    do k = 1, n_specs
      if (specs(k)%group == group .and. lower(specs(k)%name) == lower(name)) return
    end do
    k = 0
  end function spec_index

  !> The rows of a group, in table order.
  pure function group_specs(group) result(idx)
    character(len=*), intent(in) :: group
    integer, allocatable :: idx(:)
    integer :: k
    allocate(idx(0))
    do k = 1, n_specs
      if (specs(k)%group == group) idx = [idx, k]
    end do
  end function group_specs

  !> The names of the variables of a group.
  pure function var_names(group) result(names)
    character(len=*), intent(in) :: group
    character(len=16), allocatable :: names(:)
    names = specs(group_specs(group))%name
  end function var_names

  !> 'a, b, c': the variables of a group.
  pure function var_list(group) result(s)
    character(len=*), intent(in) :: group
    character(len=:), allocatable :: s
    s = join_list(var_names(group), '')
  end function var_list

  !> The names a variable of kind e accepts.
  pure function enum_names(list) result(names)
    character(len=*), intent(in) :: list   !! the variable's name
    character(len=name_len), allocatable :: names(:)
    select case (list)
    case ('basis'); names = basis_names
    case ('scheme'); names = scheme_names
    case ('plane'); names = plane_names
    case ('volumetric'); names = volumetric_names
    case ('model'); names = model_names
    case ('rate_law'); names = rate_law_names
    case ('flow_stress'); names = flow_stress_names
    case ('shape'); names = shape_names
    case ('sector'); names = sector_names
    case ('contact'); names = contact_names
    case ('law'); names = contact_names(1:3)  ! between bodies: no mirror plane ('slip')
    case default; allocate(names(0))
    end select
  end function enum_names

  !> What a variable accepts, for messages (units in brackets, default in parentheses).
  pure function allowed_text(group, var) result(s)
    character(len=*), intent(in) :: group, var
    character(len=:), allocatable :: s
    integer :: k
    k = spec_index(group, var)
    if (k == 0) then
      s = 'see docs/input.md'
    else if (specs(k)%kind == 'e') then
      s = enum_text(enum_names(trim(specs(k)%name)), trim(specs(k)%c0))
    else
      s = trim(specs(k)%allowed)
    end if
  end function allowed_text

  !> The echo's comment of row k when its value is not set: the row's unset_note, or for a
  !! required row without one 'required: ' and its comment.
  pure function unset_note(k) result(s)
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    s = trim(specs(k)%unset_note)
    if (len(s) == 0 .and. specs(k)%required) s = 'required: '//trim(specs(k)%comment)
  end function unset_note

  !> The echo's comment of row k (% replaced by the list of names).
  pure function echo_comment(k) result(s)
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    integer :: p
    s = trim(specs(k)%comment)
    p = index(s, '%')
    if (p > 0) s = s(1:p-1)//join_list(enum_names(trim(specs(k)%name)), '')//s(p+1:)
  end function echo_comment
  !> The fields of record k of group ig of cfg (for walls: cfg%walls(k)): one line per row,
  !! the only place that ties a row to its component of config_t.
  subroutine bind_fields(cfg, ig, k, f)
    type(config_t), intent(in), target :: cfg  !! the case (its records must stay in place)
    integer, intent(in) :: ig, k               !! group, record
    type(field_t), intent(out) :: f(n_specs)   !! by row of the table
    select case (ig)
    case (1)
      associate (g => cfg%run)
        call bind(f, 'run', 'title', c=g%title)
        call bind(f, 'run', 'output_dir', c=g%output_dir)
        call bind(f, 'run', 't_end', x=g%t_end)
        call bind(f, 'run', 'cfl', x=g%cfl)
        call bind(f, 'run', 'dt', x=g%dt)
        call bind(f, 'run', 'history_every', x=g%history_every)
        call bind(f, 'run', 'snapshot_every', x=g%snapshot_every)
        call bind(f, 'run', 'checkpoint_every', x=g%checkpoint_every)
        call bind(f, 'run', 'depth', x=g%depth)
        call bind(f, 'run', 'gravity', v=g%gravity)
        call bind(f, 'run', 'threads', i=g%threads)
        call bind(f, 'run', 'mirror_images', l=g%mirror_images)
        call bind(f, 'run', 'end_at_release', l=g%end_at_release)
        call bind(f, 'run', 'check_units', l=g%check_units)
      end associate
    case (2)
      associate (g => cfg%solver)
        call bind(f, 'solver', 'basis', c=g%basis, i=g%basis_id)
        call bind(f, 'solver', 'scheme', c=g%scheme, i=g%scheme_id)
        call bind(f, 'solver', 'flip', x=g%flip)
        call bind(f, 'solver', 'plane', c=g%plane, i=g%plane_id)
        call bind(f, 'solver', 'volumetric', c=g%volumetric, i=g%volumetric_id)
        call bind(f, 'solver', 'mass_scale', x=g%mass_scale)
        call bind(f, 'solver', 'damping', x=g%damping)
        call bind(f, 'solver', 'deterministic', l=g%deterministic)
      end associate
    case (3)
      associate (g => cfg%grid)
        call bind(f, 'grid', 'h', x=g%h)
        call bind(f, 'grid', 'lower', v=g%lower)
        call bind(f, 'grid', 'upper', v=g%upper)
      end associate
    case (4)
      associate (g => cfg%materials(k))
        call bind(f, 'material', 'name', c=g%name)
        call bind(f, 'material', 'model', c=g%model, i=g%model_id)
        call bind(f, 'material', 'E', x=g%E)
        call bind(f, 'material', 'nu', x=g%nu)
        call bind(f, 'material', 'rho', x=g%rho)
        call bind(f, 'material', 'sigma_y', x=g%sigma_y)
        call bind(f, 'material', 'hardening', x=g%hardening)
        call bind(f, 'material', 'voce_q', x=g%voce_q)
        call bind(f, 'material', 'voce_b', x=g%voce_b)
        call bind(f, 'material', 'rate_law', c=g%rate_law, i=g%rate_law_id)
        call bind(f, 'material', 'cs_d', x=g%cs_d)
        call bind(f, 'material', 'cs_q', x=g%cs_q)
        call bind(f, 'material', 'flow_stress', c=g%flow_stress, i=g%flow_stress_id)
        call bind(f, 'material', 'jc_b', x=g%jc_b)
        call bind(f, 'material', 'jc_n', x=g%jc_n)
        call bind(f, 'material', 'jc_c', x=g%jc_c)
        call bind(f, 'material', 'jc_rate0', x=g%jc_rate0)
        call bind(f, 'material', 'sigma_p', x=g%sigma_p)
        call bind(f, 'material', 'nu_plastic', x=g%nu_plastic)
        call bind(f, 'material', 'foam_alpha', x=g%foam_alpha)
        call bind(f, 'material', 'foam_gamma', x=g%foam_gamma)
        call bind(f, 'material', 'foam_alpha2', x=g%foam_alpha2)
        call bind(f, 'material', 'foam_beta', x=g%foam_beta)
        call bind(f, 'material', 'eps_d', x=g%eps_d)
        call bind(f, 'material', 'curve_strain', v=g%curve_strain, i=g%n_curve)
        call bind(f, 'material', 'curve_stress', v=g%curve_stress, i=g%n_curve)
      end associate
    case (5)
      associate (g => cfg%bodies(k))
        call bind(f, 'body', 'shape', c=g%shape, i=g%shape_id)
        call bind(f, 'body', 'material', c=g%material)
        call bind(f, 'body', 'center', v=g%center)
        call bind(f, 'body', 'r_inner', x=g%r_inner)
        call bind(f, 'body', 'r_outer', x=g%r_outer)
        call bind(f, 'body', 'n_thick', i=g%n_thick)
        call bind(f, 'body', 'n_circ', i=g%n_circ)
        call bind(f, 'body', 'sector', c=g%sector, i=g%sector_id)
        call bind(f, 'body', 'self_contact', l=g%self_contact)
        call bind(f, 'body', 'size', v=g%size)
        call bind(f, 'body', 'n_x', i=g%n_x)
        call bind(f, 'body', 'n_y', i=g%n_y)
        call bind(f, 'body', 'vertices', v=g%vertices, i=g%n_vertices)
        call bind(f, 'body', 'thickness', x=g%thickness)
        call bind(f, 'body', 'corner_radius', x=g%corner_radius)
        call bind(f, 'body', 'n_cells', iv=g%n_cells)
        call bind(f, 'body', 'cell_l', x=g%cell_l)
        call bind(f, 'body', 'cell_h', x=g%cell_h)
        call bind(f, 'body', 'cell_angle', x=g%cell_angle)
        call bind(f, 'body', 'walls_file', c=g%walls_file)
        call bind(f, 'body', 'velocity', v=g%velocity)
      end associate
    case (6)
      associate (g => cfg%walls(k))
        call bind(f, 'wall', 'point', v=g%point)
        call bind(f, 'wall', 'normal', v=g%normal)
        call bind(f, 'wall', 'contact', c=g%contact, i=g%contact_id)
        call bind(f, 'wall', 'friction', x=g%friction)
        call bind(f, 'wall', 'velocity', v=g%velocity)
        call bind(f, 'wall', 'ramp', x=g%ramp)
        call bind(f, 'wall', 'motion_t', v=g%motion_t, i=g%n_motion)
        call bind(f, 'wall', 'motion_f', v=g%motion_f, i=g%n_motion)
        call bind(f, 'wall', 'mass', x=g%mass)
        call bind(f, 'wall', 'stroke', x=g%stroke)
      end associate
    case (7)
      call bind(f, 'probe', 'point', v=cfg%probes(k)%point)
    case (8)
      associate (g => cfg%contacts(k))
        call bind(f, 'contact', 'bodies', iv=g%bodies)
        call bind(f, 'contact', 'law', c=g%law, i=g%law_id)
        call bind(f, 'contact', 'friction', x=g%friction)
      end associate
    end select
  end subroutine bind_fields

  !> Point the field of row (group, name) at the given component(s).
  subroutine bind(f, group, name, x, v, i, iv, l, c)
    type(field_t), intent(inout) :: f(n_specs)
    character(len=*), intent(in) :: group, name
    real(wp), intent(in), target, optional :: x, v(:)
    integer, intent(in), target, optional :: i, iv(:)
    logical, intent(in), target, optional :: l
    character(len=*), intent(in), target, optional :: c
    integer :: r
    r = spec_index(group, name)
    if (present(x)) f(r)%x => x
    if (present(v)) f(r)%v => v
    if (present(i)) f(r)%i => i
    if (present(iv)) f(r)%iv => iv
    if (present(l)) f(r)%l => l
    if (present(c)) f(r)%c => c
  end subroutine bind
end module mpm_config_table
