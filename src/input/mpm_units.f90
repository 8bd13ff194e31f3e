!> Values that are possible but implausible for a tube, usually a number in the wrong unit (the
!! input is SI): the reader refuses them (`&run check_units`, mpm_config_check) with file, line
!! and allowed range; the memory budget and a case with `check_units = .false.` word them as
!! lines (advice_units).
module mpm_units
  use mpm_kinds, only: wp
  use mpm_constants, only: SHAPE_RING, SHAPE_DISC, SHAPE_TUBE, SHAPE_HONEYCOMB, SHAPE_WALLS, &
                           MODEL_J2, MODEL_FOAM
  use mpm_config_types, only: config_t
  use mpm_errors, only: append_msg
  use mpm_strings, only: rtoa, itoa
  use mpm_config_text, only: finite
  use mpm_bodies, only: body_box
  implicit none
  private

  public :: advice_units, advice_unit_issues, unit_issue_t

  real(wp), parameter :: length_max = 1.0_wp        !! lengths above this are suspect [m]
  real(wp), parameter :: e_min = 1.0e6_wp, e_max = 1.0e13_wp  !! plausible E [Pa]
  real(wp), parameter :: rho_min = 10.0_wp, rho_max = 30000.0_wp  !! plausible rho [kg/m^3]
  real(wp), parameter :: yield_strain_max = 1.0_wp/50.0_wp  !! sigma_y / E above this is suspect
  real(wp), parameter :: yield_strain_min = 1.0e-5_wp  !! sigma_y / E below this is suspect
  real(wp), parameter :: foam_strain_max = 1.0_wp/10.0_wp  !! foam sigma_p / E above this [-]
  real(wp), parameter :: foam_sigma_min = 1.0e3_wp   !! foam sigma_p below this is suspect [Pa]
  real(wp), parameter :: speed_max = 1.0e3_wp       !! speeds above this are suspect [m/s]

  !> A value that is usually a number in the wrong unit (advice_unit_issues).
  type :: unit_issue_t
    character(len=8) :: group = ''         !! its namelist group
    integer :: k = 0                       !! occurrence of a repeatable group (0: given once)
    character(len=16) :: var = ''          !! the variable
    character(len=:), allocatable :: value   !! its value, with the unit
    character(len=:), allocatable :: why     !! why it is suspect, and the likely slip
    character(len=:), allocatable :: allowed !! the plausible range
    logical :: others = .false.              !! it compares with other groups' values
  end type unit_issue_t

contains

  !> Values that are possible but implausible for a tube, usually a number in the wrong unit
  !! (the input is SI): lengths over 1 m, E outside 1 MPa .. 1e13 Pa, sigma_y above E/50,
  !! a foam's sigma_p above E/10 or below 1 kPa, density outside 10 .. 30 000 kg/m^3, a wall's
  !! or body's speed over 1000 m/s. The reader refuses them (`&run check_units`,
  !! mpm_config_check) with its file, line and allowed range; advice_units words them as lines.
  pure subroutine advice_unit_issues(cfg, issues, bodies_ok)
    type(config_t), intent(in) :: cfg      !! the case
    type(unit_issue_t), allocatable, intent(out) :: issues(:)  !! one per suspect value
    logical, intent(in), optional :: bodies_ok(:)  !! the bodies whose values are complete
    integer :: k
    character(len=*), parameter :: mm = 'over 1 m: the input is in metres (millimetres '// &
      'typed as metres?)', metres = 'a length in metres, at most 1 m', ms = 'a speed over '// &
      '1000 m/s (times the motion table''s largest factor): the input is in m/s (mm/s typed '// &
      'as m/s?)', speeds = 'a speed in m/s, at most 1000 m/s'
    allocate(issues(0))
    if (cfg%grid%h > length_max) call push(issues, 'grid', 0, 'h', rtoa(cfg%grid%h)//' m', mm, &
                                           metres)
    if (.not. cfg%grid%fitted) then
      if (maxval(abs(cfg%grid%lower)) > length_max) call push(issues, 'grid', 0, 'lower', &
        rtoa(maxval(abs(cfg%grid%lower)))//' m', mm, metres)
      if (maxval(abs(cfg%grid%upper)) > length_max) call push(issues, 'grid', 0, 'upper', &
        rtoa(maxval(abs(cfg%grid%upper)))//' m', mm, metres)
    end if
    if (cfg%grid%h <= length_max) call cell_over_bodies(cfg, issues, bodies_ok)
    do k = 1, size(cfg%bodies)
      associate (b => cfg%bodies(k))
        select case (b%shape_id)
        case (SHAPE_RING, SHAPE_DISC)
          if (b%r_outer > length_max) call push(issues, 'body', k, 'r_outer', &
                                                rtoa(b%r_outer)//' m', mm, metres)
          if (b%r_inner > length_max) call push(issues, 'body', k, 'r_inner', &
                                                rtoa(b%r_inner)//' m', mm, metres)
        case (SHAPE_TUBE)
          if (b%n_vertices > 0) then
            if (maxval(abs(b%vertices(1:2*b%n_vertices))) > length_max) call push(issues, &
              'body', k, 'vertices', rtoa(maxval(abs(b%vertices(1:2*b%n_vertices))))// &
              ' m', mm, metres)
          end if
          if (b%thickness > length_max) call push(issues, 'body', k, 'thickness', &
                                                  rtoa(b%thickness)//' m', mm, metres)
          if (b%corner_radius > length_max) call push(issues, 'body', k, 'corner_radius', &
                                                      rtoa(b%corner_radius)//' m', mm, metres)
        case (SHAPE_HONEYCOMB)
          if (max(b%cell_l, b%cell_h) > length_max) call push(issues, 'body', k, &
            trim(merge('cell_l', 'cell_h', b%cell_l >= b%cell_h)), &
            rtoa(max(b%cell_l, b%cell_h))//' m', mm, metres)
          if (b%thickness > length_max) call push(issues, 'body', k, 'thickness', &
                                                  rtoa(b%thickness)//' m', mm, metres)
        case (SHAPE_WALLS)
          if (allocated(b%seg)) then
            if (size(b%seg, 2) > 0) then
              if (maxval(abs(b%seg)) > length_max) call push(issues, 'body', k, &
                'walls_file', rtoa(maxval(abs(b%seg)))//' m', mm, metres)
            end if
          end if
        case default
          if (maxval(b%size) > length_max) call push(issues, 'body', k, 'size', &
                                                     rtoa(maxval(b%size))//' m', mm, metres)
        end select
        if (maxval(abs(b%center)) > length_max) call push(issues, 'body', k, 'center', &
          rtoa(maxval(abs(b%center)))//' m', mm, metres)
      end associate
    end do
    do k = 1, size(cfg%walls)
      if (cfg%walls(k)%mirror) cycle
      if (maxval(abs(cfg%walls(k)%point)) > length_max) call push(issues, 'wall', k, 'point', &
        rtoa(maxval(abs(cfg%walls(k)%point)))//' m', mm, metres)
      if (cfg%walls(k)%stroke > length_max) call push(issues, 'wall', k, 'stroke', &
        rtoa(cfg%walls(k)%stroke)//' m', mm, metres)
      associate (w => cfg%walls(k))             ! its fastest speed: velocity times the table
        if (.not. all(finite(w%velocity))) cycle   ! (reported where it is read)
        if (norm2(w%velocity)*merge(maxval(abs(w%motion_f(1:max(w%n_motion, 1)))), 1.0_wp, &
            w%n_motion > 0) > speed_max) call push(issues, 'wall', k, 'velocity', &
          rtoa(norm2(w%velocity))//' m/s', ms, speeds)
      end associate
    end do
    do k = 1, size(cfg%bodies)
      if (.not. all(finite(cfg%bodies(k)%velocity))) cycle   ! (reported where it is read)
      if (norm2(cfg%bodies(k)%velocity) > speed_max) call push(issues, 'body', k, 'velocity', &
        rtoa(norm2(cfg%bodies(k)%velocity))//' m/s', ms, speeds)
    end do
    do k = 1, size(cfg%materials)
      associate (m => cfg%materials(k))
        if (m%E < e_min .or. m%E > e_max) call push(issues, 'material', k, 'E', &
          rtoa(m%E)//' Pa', 'outside 1e6 .. 1e13 Pa: E is in Pa (steel 2.1e11, aluminium '// &
          '7e10, rubber about 1e6 to 1e7)', 'a real number from 1e6 to 1e13 [Pa]')
        if (m%model_id == MODEL_J2 .and. m%sigma_y > yield_strain_max*m%E) call push(issues, &
          'material', k, 'sigma_y', rtoa(m%sigma_y)//' Pa', 'above E/50 = '// &
          rtoa(yield_strain_max*m%E)//' Pa: both are in Pa (steel sigma_y about 2e8 to 1e9 '// &
          'against E = 2.1e11)', 'a real number of at most E/50 [Pa]')
        if (m%model_id == MODEL_J2 .and. m%sigma_y > 0.0_wp .and. m%sigma_y < yield_strain_min*m%E) &
          call push(issues, 'material', k, 'sigma_y', rtoa(m%sigma_y)//' Pa', 'below E/1e5 = '// &
          rtoa(yield_strain_min*m%E)//' Pa: sigma_y is in Pa (MPa typed as Pa?)', &
          'a real number from E/1e5 to E/50 [Pa], or 0 for an elastic material')
        if (m%model_id == MODEL_FOAM .and. m%sigma_p > 0.0_wp) then
          if (m%sigma_p > foam_strain_max*m%E) call push(issues, 'material', k, 'sigma_p', &
            rtoa(m%sigma_p)//' Pa', 'above E/10 = '//rtoa(foam_strain_max*m%E)//' Pa: both '// &
            'are in Pa (aluminium foam sigma_p about 1e6 to 1e7 against E = 1e8 to 1e9)', &
            'a real number of at most E/10 [Pa]')
          if (m%sigma_p < foam_sigma_min) call push(issues, 'material', k, 'sigma_p', &
            rtoa(m%sigma_p)//' Pa', 'below 1e3 Pa: sigma_p is in Pa (MPa typed as Pa?)', &
            'a real number of at least 1e3 [Pa]')
        end if
        if (m%rho < rho_min .or. m%rho > rho_max) call push(issues, 'material', k, 'rho', &
          rtoa(m%rho)//' kg/m^3', 'outside 10 .. 30000 kg/m^3: rho is in kg/m^3 (steel 7800, '// &
          'aluminium 2700; g/cm^3 times 1000)', 'a real number from 10 to 30000 [kg/m^3]')
      end associate
    end do
  end subroutine advice_unit_issues

  !> A cell larger than every body (the part a sector models): a body in one or two cells, a
  !! cell size in millimetres typed as metres.
  pure subroutine cell_over_bodies(cfg, issues, bodies_ok)
    type(config_t), intent(in) :: cfg
    type(unit_issue_t), allocatable, intent(inout) :: issues(:)
    logical, intent(in), optional :: bodies_ok(:)  !! the bodies whose values are complete
    integer :: k, kb
    real(wp) :: span, lo(2), hi(2)
    span = 0.0_wp
    kb = 0
    do k = 1, size(cfg%bodies)
      if (present(bodies_ok)) then
        if (.not. bodies_ok(k)) cycle
      end if
      if (cfg%bodies(k)%shape_id == SHAPE_WALLS .and. .not. allocated(cfg%bodies(k)%seg)) cycle
      call body_box(cfg%bodies(k), lo, hi)
      if (.not. (all(hi > lo) .and. maxval(hi - lo) > span)) cycle
      kb = k
      span = maxval(hi - lo)
    end do
    if (kb == 0 .or. .not. cfg%grid%h > span) return
    call push(issues, 'grid', 0, 'h', rtoa(cfg%grid%h)//' m', 'larger than every body (the '// &
      'largest, &body #'//itoa(kb)//', spans '//rtoa(span)//' m as modelled): a body would '// &
      'sit in one or two cells (millimetres typed as metres?)', 'a cell smaller than the '// &
      'bodies, h < '//rtoa(span)//' m (the refinement study advises h = t/4)')
    issues(size(issues))%others = .true.
  end subroutine cell_over_bodies

  !> The values in a likely wrong unit as lines ('&body #1: r_outer = 2.6000E+001 m is over
  !! 1 m. Set r_outer in m (docs/input.md#checks)'), appended to `text`: the warnings of a case
  !! with `check_units = .false.` and the hints of a refused memory budget.
  pure subroutine advice_units(cfg, text)
    type(config_t), intent(in) :: cfg      !! the case
    character(len=:), allocatable, intent(inout) :: text  !! lines so far (may be unallocated)
    type(unit_issue_t), allocatable :: issues(:)
    integer :: j
    character(len=:), allocatable :: where
    if (.not. allocated(text)) text = ''
    call advice_unit_issues(cfg, issues)
    do j = 1, size(issues)
      associate (u => issues(j))
        where = '&'//trim(u%group)
        if (u%k > 0) where = where//' #'//itoa(u%k)
        call append_msg(text, where//': '//trim(u%var)//' = '//u%value//' is '// &
          u%why(1:index(u%why//':', ':') - 1)//'. Set it in '// &
          u%value(index(u%value, ' ') + 1:)//' (docs/input.md#checks)')
      end associate
    end do
  end subroutine advice_units

  !> Append one issue.
  pure subroutine push(issues, group, k, var, value, why, allowed)
    type(unit_issue_t), allocatable, intent(inout) :: issues(:)
    character(len=*), intent(in) :: group, var, value, why, allowed
    integer, intent(in) :: k               !! occurrence (0: a group given once)
    issues = [issues, unit_issue_t(group, k, var, value, why, allowed)]
  end subroutine push

end module mpm_units
