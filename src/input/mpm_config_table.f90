!> The input variables: one row per namelist variable, what it accepts and what it means. The
!! variable itself (its type, size and default) is the component of its group's type
!! (mpm_config_types); a row adds the range the checks hold it to, the text of "allowed:" in
!! messages, the comment of the resolved echo (input.nml), and which body shapes or material
!! model it belongs to. tests/test_docs_input.py compares the rows with docs/input.md.
! SPDX-License-Identifier: MIT
module mpm_config_table
  use mpm_kinds, only: wp
  use mpm_constants, only: name_len, basis_names, scheme_names, plane_names, model_names, &
                           rate_law_names, shape_names, sector_names, contact_names, &
                           flow_stress_names, volumetric_names
  use mpm_config_text, only: join_list, lower, itoa, fmt_real, fmt_short, finite
  implicit none
  private
  public :: var_spec_t, specs, n_groups, group_names, group_repeatable, group_id, spec_index, &
            vmax, magnitude_bounds, beyond, &
            group_specs, var_names, enum_names, echo_comment, unset_note

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
    logical :: required = .false.
    real(wp) :: lo = -big, hi = big                  !! admissible range
    logical :: lo_open = .false., hi_open = .false.  !! lo < x (not <=), x < hi (not <=)
    character(len=40) :: only = ''          !! body shapes, or the &material model, it is for
                                            !! (names separated by blanks; '' = all)
    character(len=4) :: unset = ''          !! echo: a required value is not set when neg (-1),
                                            !! huge (unset_real), emp (empty text), zero
    character(len=56) :: unset_note = ''    !! echo comment when not set
    character(len=160) :: allowed = ''      !! "allowed:" text of messages, units in brackets,
                                            !! default in parentheses ('' for a list of names:
                                            !! made from the list)
    character(len=48) :: comment = ''       !! echo comment: meaning [unit]; % = the names
    logical :: quiet = .false.              !! left out of the echo while at its default
  end type var_spec_t

  character(len=*), parameter :: s0 = 'a real number >= 0 [s] (default 0)'
  real(wp), parameter :: vmax = 1.0e5_wp   !! no tube is struck faster [m/s]; nor is a number
                                         !! without a unit (a motion factor) larger
  character(len=*), parameter :: v0 = '2 real numbers from -1e5 to 1e5 [m/s] (default 0, 0)'
  character(len=*), parameter :: lu = '2 real numbers [m] each for lower and upper, lower '// &
    '< upper in both components, both given or neither (then fitted)'

  !> The magnitudes the program takes, by the unit of a row's comment, with check_units or
  !! without: beyond them the set-up's arithmetic overflows (a length of 1e300 m, a thickness of
  !! 1e-300 m), far beyond any tube. big: the largest |value|; small: the smallest value other
  !! than 0 of a quantity that is not negative (lo >= 0). Speeds: their rows' range (vmax).
  type :: magnitude_t
    character(len=8) :: unit = ''
    real(wp) :: big = 0.0_wp, small = 0.0_wp
  end type magnitude_t
  type(magnitude_t), parameter :: magnitudes(*) = [magnitude_t('m', 1.0e3_wp, 1.0e-9_wp), &
    magnitude_t('s', 1.0e6_wp, 1.0e-15_wp), magnitude_t('Pa', 1.0e15_wp, 1.0e-3_wp), &
    magnitude_t('kg/m^3', 1.0e6_wp, 1.0e-6_wp), magnitude_t('kg', 1.0e9_wp, 1.0e-9_wp), &
    magnitude_t('m/s^2', 1.0e9_wp, 0.0_wp), &
    magnitude_t('1/s', 1.0e12_wp, 1.0e-12_wp), magnitude_t('-', vmax, 0.0_wp)]

  type(var_spec_t), parameter :: specs(*) = [ &
    ! ---------------------------------------------------------------------------- &run
    var_spec_t('run', 'title', unset='emp', unset_note='default: the file name stem', &
      allowed='text of at most 64 characters (default: the file name stem)', &
      comment='label of the case'), &
    var_spec_t('run', 'output_dir', unset='emp', unset_note='default: out/<title>', &
      allowed='a folder path of at most 512 characters (default: out/<title>)', &
      comment='folder for all outputs'), &
    var_spec_t('run', 't_end', lo=0.0_wp, lo_open=.true., unset='neg', &
      unset_note='default: when every moving wall has reached its stroke', &
      allowed='a real number > 0 [s] (required unless every moving &wall has a stroke)', &
      comment='simulated time [s]'), &
    var_spec_t('run', 'cfl', lo=0.0_wp, hi=2.0_wp, &
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
    var_spec_t('run', 'depth', lo=0.0_wp, lo_open=.true., &
      allowed='a real number > 0 [m] (default 1.0)', comment='out-of-plane length [m]'), &
    var_spec_t('run', 'gravity', allowed='2 finite real numbers [m/s^2] (default 0, 0)', &
      comment='body acceleration [m/s^2]'), &
    var_spec_t('run', 'threads', lo=0.0_wp, &
      allowed='an integer >= 0 (0 = one per core that other work does not keep busy)', &
      comment='OpenMP threads (0 = runtime default)'), &
    var_spec_t('run', 'mirror_images', allowed='.true. or .false. (default .true.)', &
      comment='write the mirror images of a sector', quiet=.true.), &
    var_spec_t('run', 'end_at_release', allowed='.true. or .false. (default .false.)', &
      comment='end the run when its contact is over', quiet=.true.), &
    var_spec_t('run', 'check_units', allowed='.true. or .false. (default '// &
      '.true.: refuse values that are usually a wrong unit)', &
      comment='refuse values in a likely wrong unit', quiet=.true.), &
    ! ---------------------------------------------------------------------------- &solver
    var_spec_t('solver', 'basis', comment='% [-]'), &
    var_spec_t('solver', 'scheme', comment='% [-]'), &
    var_spec_t('solver', 'flip', lo=0.0_wp, hi=1.0_wp, &
      allowed='a real number with 0 <= flip <= 1 (default 1.0)', &
      comment='FLIP fraction (1 FLIP, 0 PIC) [-]'), &
    var_spec_t('solver', 'plane', comment='% [-]'), &
    var_spec_t('solver', 'volumetric', comment='% (fbar: anti-locking) [-]'), &
    var_spec_t('solver', 'mass_scale', lo=1.0_wp, &
      allowed='a real number >= 1 (default 1.0)', comment='density multiplier [-]'), &
    var_spec_t('solver', 'damping', lo=0.0_wp, allowed='a real number >= 0 [1/s] (default 0)', &
      comment='mass-proportional damping [1/s]'), &
    var_spec_t('solver', 'deterministic', allowed='.true. or .false. (default .false.)', &
      comment='results independent of the thread count'), &
    ! ---------------------------------------------------------------------------- &grid
    var_spec_t('grid', 'h', required=.true., lo=0.0_wp, lo_open=.true., unset='neg', &
      allowed='a real number > 0 [m] (required)', comment='cell size [m]'), &
    var_spec_t('grid', 'lower', allowed=lu, comment='lower domain corner [m]'), &
    var_spec_t('grid', 'upper', allowed=lu, comment='upper domain corner [m]'), &
    ! ---------------------------------------------------------------------------- &material
    var_spec_t('material', 'name', required=.true., unset='emp', &
      allowed='text of 1 to 64 characters, unique among the &material groups (required)', &
      comment='label used by &body'), &
    var_spec_t('material', 'model', comment='%'), &
    var_spec_t('material', 'E', required=.true., lo=0.0_wp, lo_open=.true., &
      unset='neg', allowed='a real number > 0 [Pa] (required)', comment='Young''s modulus [Pa]'), &
    var_spec_t('material', 'nu', required=.true., lo=0.0_wp, hi=0.5_wp, hi_open=.true., &
      unset='neg', allowed='a real number with 0 <= nu < 0.5 (required)', &
      comment='Poisson''s ratio [-]'), &
    var_spec_t('material', 'rho', required=.true., lo=0.0_wp, lo_open=.true., &
      unset='neg', allowed='a real number > 0 [kg/m^3] (required)', comment='density [kg/m^3]'), &
    var_spec_t('material', 'sigma_y', lo=0.0_wp, lo_open=.true., unset='neg', &
      unset_note='required for model = ''j2'': initial yield stress [Pa]', &
      allowed='a real number > 0 [Pa] (required for model = ''j2'')', &
      comment='initial yield stress [Pa]'), &
    var_spec_t('material', 'hardening', lo=0.0_wp, allowed='a real number >= 0 [Pa] '// &
      '(default 0)', comment='linear isotropic hardening modulus [Pa]'), &
    var_spec_t('material', 'voce_q', lo=0.0_wp, quiet=.true., allowed='a real number >= 0 '// &
      '[Pa] (default 0: no saturation term)', comment='Voce saturation stress Q [Pa]'), &
    var_spec_t('material', 'voce_b', lo=0.0_wp, lo_open=.true., quiet=.true., &
      allowed='a real number > 0 (default 10)', comment='Voce saturation rate b [-]'), &
    var_spec_t('material', 'rate_law', comment='%'), &
    var_spec_t('material', 'cs_d', lo=0.0_wp, lo_open=.true., &
      allowed='a real number > 0 [1/s] (default 40.4)', comment='Cowper-Symonds D [1/s]'), &
    var_spec_t('material', 'cs_q', lo=0.1_wp, hi=100.0_wp, &
      allowed='a real number from 0.1 to 100 (default 5)', comment='Cowper-Symonds q [-]'), &
    var_spec_t('material', 'flow_stress', comment='%'), &
    var_spec_t('material', 'jc_b', lo=0.0_wp, allowed='a real number >= 0 [Pa] (default 0)', &
      comment='Johnson-Cook B [Pa]'), &
    var_spec_t('material', 'jc_n', lo=0.0_wp, lo_open=.true., hi=1.0_wp, &
      allowed='a real number with 0 < jc_n <= 1 (default 1)', comment='Johnson-Cook n [-]'), &
    var_spec_t('material', 'jc_c', lo=0.0_wp, allowed='a real number >= 0 (default 0)', &
      comment='Johnson-Cook C [-]'), &
    var_spec_t('material', 'jc_rate0', lo=0.0_wp, lo_open=.true., &
      allowed='a real number > 0 [1/s] (default 1)', &
      comment='Johnson-Cook reference strain rate [1/s]'), &
    var_spec_t('material', 'sigma_p', lo=0.0_wp, lo_open=.true., &
      only='foam', unset='neg', allowed='a real number > 0 [Pa] (required for model = '// &
      '''foam'' without curve_strain, curve_stress)', comment='foam plateau stress [Pa]'), &
    var_spec_t('material', 'nu_plastic', lo=-1.0_wp, lo_open=.true., &
      hi=0.5_wp, hi_open=.true., only='foam', allowed='a real number with -1 < nu_plastic '// &
      '< 0.5, not with foam_alpha (default 0: alpha = 2.12)', &
      comment='foam plastic Poisson''s ratio [-]'), &
    var_spec_t('material', 'foam_alpha', lo=0.0_wp, lo_open=.true., &
      only='foam', unset='neg', unset_note='default: from nu_plastic', allowed='a real '// &
      'number > 0, not with nu_plastic (default: from nu_plastic)', &
      comment='foam yield surface shape alpha [-]'), &
    var_spec_t('material', 'foam_gamma', lo=0.0_wp, only='foam', allowed='a real number '// &
      '>= 0 [Pa], not with a curve (default 0)', comment='foam hardening gamma [Pa]'), &
    var_spec_t('material', 'foam_alpha2', lo=0.0_wp, only='foam', allowed='a real number '// &
      '>= 0 [Pa], not with a curve (default 0)', comment='foam densification alpha2 [Pa]'), &
    var_spec_t('material', 'foam_beta', lo=0.01_wp, hi=100.0_wp, only='foam', &
      allowed='a real number from 0.01 to 100, not with a curve (default 1)', &
      comment='foam densification exponent beta [-]'), &
    var_spec_t('material', 'eps_d', lo=1.0e-3_wp, hi=10.0_wp, &
      only='foam', unset='neg', allowed='a real number from 0.001 to 10 (required for model '// &
      '= ''foam'' '// &
      'without curve_strain, curve_stress)', comment='foam densification strain [-]'), &
    var_spec_t('material', 'curve_strain', only='foam', &
      allowed='up to 64 plastic strains, the first 0, strictly increasing, as many as '// &
      'curve_stress (default none: the law)', comment='plastic strains [-]'), &
    var_spec_t('material', 'curve_stress', only='foam', &
      allowed='up to 64 yield stresses > 0 [Pa], not decreasing, as many as '// &
      'curve_strain (default none)', comment='uniaxial yield stresses [Pa]'), &
    ! ---------------------------------------------------------------------------- &body
    var_spec_t('body', 'shape', comment='%'), &
    var_spec_t('body', 'material', unset='emp', unset_note='default: the first material', &
      allowed='the name of a &material (default: the first material)', &
      comment='a &material name'), &
    var_spec_t('body', 'center', allowed='2 finite real numbers [m] (default 0, 0)', &
      comment='centre [m]'), &
    var_spec_t('body', 'r_inner', required=.true., lo=0.0_wp, lo_open=.true., &
      only='ring', unset='neg', &
      allowed='a real number with 0 < r_inner < r_outer [m] (required for shape = ''ring'')', &
      comment='inner radius [m]'), &
    var_spec_t('body', 'r_outer', required=.true., lo=0.0_wp, lo_open=.true., &
      only='ring disc', unset='neg', &
      allowed='a real number > r_inner [m] (required for shape = ''ring'' and ''disc'')', &
      comment='outer radius [m]'), &
    var_spec_t('body', 'n_thick', lo=1.0_wp, hi=256.0_wp, &
      only='ring tube honeycomb walls disc filler', &
      allowed='an integer from 1 to 256, even where three walls meet at an angle (default 16)', &
      comment='particles through the wall (disc: radius)'), &
    var_spec_t('body', 'n_circ', only='ring', &
      allowed='0 (particles about square) or an integer >= 3, divisible by 2 for sector = '// &
      '''half'' and by 4 for ''quarter'' (default 0)', &
      comment='particles around the whole ring (0 = auto)'), &
    var_spec_t('body', 'sector', only='ring tube walls disc', comment='%'), &
    var_spec_t('body', 'self_contact', only='ring tube honeycomb walls', allowed='.true. or '// &
      '.false. (default .false.); .true. needs sector = ''full'' or ''half''', &
      comment='walls meet, never weld'), &
    var_spec_t('body', 'size', required=.true., lo=0.0_wp, lo_open=.true., &
      only='rect', unset='neg', allowed='2 real numbers > 0 [m] (required for shape = ''rect'')', &
      comment='rectangle sides [m]'), &
    var_spec_t('body', 'n_x', required=.true., lo=1.0_wp, only='rect', unset='zero', &
      allowed='an integer >= 1 (required for shape = ''rect'')', comment='particles along x'), &
    var_spec_t('body', 'n_y', required=.true., lo=1.0_wp, only='rect', unset='zero', &
      allowed='an integer >= 1 (required for shape = ''rect'')', comment='particles along y'), &
    var_spec_t('body', 'vertices', only='tube', &
      allowed='3 to 64 points x, y [m] of the centreline polygon, counter-clockwise, '// &
      'finite (required for shape = ''tube'')', comment='centreline polygon x, y, ... [m]'), &
    var_spec_t('body', 'thickness', required=.true., lo=0.0_wp, lo_open=.true., &
      only='tube honeycomb', unset='neg', allowed='a real number > 0 [m] (required for '// &
      'shape = ''tube'' and ''honeycomb'')', comment='wall thickness [m]'), &
    var_spec_t('body', 'corner_radius', lo=0.0_wp, only='tube', allowed='0 (sharp) or a '// &
      'real number >= thickness/2 [m] whose rounded corners fit their sides (default 0)', &
      comment='corner radius, centreline [m]'), &
    var_spec_t('body', 'n_cells', required=.true., lo=1.0_wp, hi=64.0_wp, only='honeycomb', &
      unset='zero', allowed='2 whole numbers from 1 to 64: cells along x and y (required '// &
      'for shape = ''honeycomb'')', comment='cells along x and y'), &
    var_spec_t('body', 'cell_l', required=.true., lo=0.0_wp, lo_open=.true., &
      only='honeycomb', unset='neg', allowed='a real number > 0 [m] (required for shape '// &
      '= ''honeycomb'')', comment='inclined wall length [m]'), &
    var_spec_t('body', 'cell_h', required=.true., lo=0.0_wp, lo_open=.true., &
      only='honeycomb', unset='neg', allowed='a real number > 0 [m] (required for shape '// &
      '= ''honeycomb'')', comment='vertical wall length [m]'), &
    var_spec_t('body', 'cell_angle', lo=-80.0_wp, hi=80.0_wp, only='honeycomb', &
      allowed='a real number from -80 to 80 [degrees], |angle| >= 1, with cell_h + '// &
      '2 cell_l sin(angle) > thickness (default 30)', comment='inclined wall angle to x [deg]'), &
    var_spec_t('body', 'walls_file', required=.true., unset='emp', &
      only='walls', allowed='a CSV file (relative to the input file''s folder), one wall '// &
      'per line: x1, y1, x2, y2, thickness [m] (required for shape = ''walls'')', &
      comment='CSV of walls: x1, y1, x2, y2, t'), &
    var_spec_t('body', 'fills', required=.true., lo=1.0_wp, only='filler', unset='zero', &
      allowed='the number of a ''tube'' &body given before', comment='the tube it fills'), &
    var_spec_t('body', 'fill_gap', lo=0.0_wp, only='filler', allowed='a real number >= 0 '// &
      '[m] (default 0)', comment='gap to the tube''s inner face [m]'), &
    var_spec_t('body', 'velocity', lo=-vmax, hi=vmax, allowed=v0, &
      comment='initial velocity [m/s]'), &
    ! ---------------------------------------------------------------------------- &wall
    var_spec_t('wall', 'point', required=.true., unset='huge', &
      allowed='2 finite real numbers [m] (required)', &
      comment='a point on the plane at t = 0 [m]'), &
    var_spec_t('wall', 'normal', required=.true., unset='huge', &
      allowed='2 real numbers forming a unit vector, |normal| = 1 within 1e-6 (required)', &
      comment='unit normal into the material side [-]'), &
    var_spec_t('wall', 'contact', comment='%'), &
    var_spec_t('wall', 'friction', lo=0.0_wp, allowed='a real number >= 0, and > 0 only '// &
      'with contact = ''coulomb'' or ''bonded'' (default 0)', &
      comment='Coulomb coefficient [-]'), &
    var_spec_t('wall', 'velocity', lo=-vmax, hi=vmax, allowed=v0, &
      comment='prescribed velocity [m/s]'), &
    var_spec_t('wall', 'ramp', lo=0.0_wp, allowed='a real number >= 0 [s] (default 0)', &
      comment='smooth rise time of the velocity [s]'), &
    var_spec_t('wall', 'motion_t', allowed='up to 64 times [s], >= 0 and '// &
      'strictly increasing, as many as motion_f (default none)', comment='times [s]'), &
    var_spec_t('wall', 'motion_f', allowed='up to 64 factors from -1e5 to 1e5, '// &
      'as many '// &
      'as motion_t (default none)', comment='factors on velocity [-]'), &
    var_spec_t('wall', 'mass', lo=0.0_wp, allowed='a real number >= 0 [kg] (0: prescribed '// &
      'motion; > 0: a free rigid body, for depth; default 0)', &
      comment='> 0: drop weight of this mass [kg]'), &
    var_spec_t('wall', 'stroke', lo=0.0_wp, allowed='a real number >= 0 [m] (0: none; '// &
      'default 0)', comment='> 0: eases to rest at this travel [m]'), &
    var_spec_t('wall', 'penalty', lo=1.0_wp, hi=4.0_wp, quiet=.true., allowed='a real '// &
      'number from 1 to 4, and above 1 only with a contact law other than ''slip'' '// &
      '(default 1)', comment='penalty stiffness over the default [-]'), &
    ! ---------------------------------------------------------------------------- &probe
    var_spec_t('probe', 'point', required=.true., unset='huge', &
      allowed='2 finite real numbers [m] (required)', &
      comment='the particle nearest to it is recorded [m]'), &
    ! ---------------------------------------------------------------------------- &contact
    var_spec_t('contact', 'bodies', lo=0.0_wp, hi=1.0e6_wp, &
      allowed='2 integers: two different bodies by their order in the file (1, 2, ...), '// &
      'or 0, 0 for every pair not named in another &contact (default 0, 0)', &
      comment='the two bodies (0, 0 = every other pair) [-]'), &
    var_spec_t('contact', 'law', comment='%'), &
    var_spec_t('contact', 'friction', lo=0.0_wp, allowed='a real number >= 0, and > 0 only '// &
      'with law = ''coulomb'' or ''bonded'' (default 0)', comment='Coulomb coefficient [-]')]

contains

  !> Index of a group name in group_names, 0 if unknown.
  pure integer function group_id(name)
    character(len=*), intent(in) :: name   !! group name, lower case
    group_id = findloc(group_names, name, 1)
  end function group_id

  !> Row of variable `name` (case-insensitive) of a group, 0 if none.
  pure integer function spec_index(group, name) result(k)
    character(len=*), intent(in) :: group, name
    k = findloc(specs%group == group .and. lower(specs%name) == lower(name), .true., 1)
  end function spec_index

  !> The rows of a group, in table order.
  pure function group_specs(group) result(idx)
    character(len=*), intent(in) :: group
    integer, allocatable :: idx(:)
    integer :: k
    idx = pack([(k, k = 1, size(specs))], specs%group == group)
  end function group_specs

  !> The names of the variables of a group.
  pure function var_names(group) result(names)
    character(len=*), intent(in) :: group
    character(len=16), allocatable :: names(:)
    names = specs(group_specs(group))%name
  end function var_names

  !> The names a variable that is one of a list accepts (none for other variables).
  pure function enum_names(name) result(names)
    character(len=*), intent(in) :: name   !! the variable's name
    character(len=name_len), allocatable :: names(:)
    select case (name)
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
    case ('law'); names = contact_names([1, 2, 3, 5])  ! not 'slip' (check_contact: the 4th)
    case default; allocate(names(0))
    end select
  end function enum_names

  !> The echo's comment of row k when its value is not set: the row's unset_note, or for a
  !! required row without one 'required: ' and its comment.
  pure function unset_note(k) result(s)
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    s = trim(specs(k)%unset_note)
    if (len(s) == 0 .and. specs(k)%required) s = 'required: '//trim(specs(k)%comment)
  end function unset_note

  !> The magnitudes row k takes (its unit's; big = huge and small = 0 without a unit), and the
  !! unit ('' without one).
  pure subroutine magnitude_bounds(k, big, small, unit)
    integer, intent(in) :: k
    real(wp), intent(out) :: big, small
    character(len=:), allocatable, intent(out) :: unit
    integer :: p, j
    big = huge(1.0_wp)
    small = 0.0_wp
    unit = ''
    p = index(specs(k)%comment, '[', back=.true.)
    if (p == 0) return
    unit = specs(k)%comment(p+1:index(specs(k)%comment, ']', back=.true.) - 1)
    do j = 1, size(magnitudes)   ! (a loop: gfortran 12.2's findloc of a deferred-length text in
      if (magnitudes(j)%unit /= unit) cycle   ! a component array broke the module's findlocs)
      big = magnitudes(j)%big
      if (specs(k)%lo >= 0.0_wp) small = magnitudes(j)%small
    end do
  end subroutine magnitude_bounds

  !> '' when the finite values of row r are within the magnitudes the program takes
  !! (magnitude_bounds), else which one is not and the bounds; huge values (a table's entries
  !! not given) are passed over.
  function beyond(r, x) result(what)
    integer, intent(in) :: r
    real(wp), intent(in) :: x(:)
    character(len=:), allocatable :: what
    real(wp) :: big, small
    character(len=:), allocatable :: unit
    integer :: j
    what = ''
    call magnitude_bounds(r, big, small, unit)
    do j = 1, size(x)
      if (.not. finite(x(j)) .or. x(j) == huge(1.0_wp)) cycle
      if (abs(x(j)) <= big .and. .not. (x(j) /= 0.0_wp .and. abs(x(j)) < small)) cycle
      if (size(x) > 1) what = trim(specs(r)%name)//'('//itoa(j)//') = '//fmt_real(x(j))//': '
      if (unit == '-') unit = ''
      if (len(unit) > 0) unit = ' '//unit
      what = what//'beyond the limits of the program: up to '//fmt_short(big)//unit//' in size'
      if (small > 0.0_wp) what = what//', 0 or at least '//fmt_short(small)//unit
      return
    end do
  end function beyond

  !> The echo's comment of row k (% replaced by the list of names).
  pure function echo_comment(k) result(s)
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    integer :: p
    s = trim(specs(k)%comment)
    p = index(s, '%')
    if (p > 0) s = s(1:p-1)//join_list(enum_names(trim(specs(k)%name)), '')//s(p+1:)
  end function echo_comment
end module mpm_config_table
