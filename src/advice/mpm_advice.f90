!> One home for what the studies found, as advice: the warnings of `tubempm --check` (and of
!! the start of a run) about the set-up and the end-of-run warning on the energy balance; what
!! the refinement study says about an input is mpm_study_advice's. Nothing on the way from the
!! input to the results uses it: only the report of the set-up (mpm_report) and the driver's
!! end of run.
!!
!! The data are compiled in from generated tables (tools/advice_tables.py writes them):
!! src/advice/mpm_stability_table.inc (the largest cfl at which the stability study's impact
!! scene completes, per basis and scheme, docs/stability/cfl_limits_ppc*.csv; the wall-time
!! estimate and its tables are mpm_cost's). Its rows are found
!! by the names of the basis and scheme: a basis or scheme no study has run has no advice. The
!! automatic cfl and its table are the time step's (mpm_time_step). The errors hold for the
!! studies' scenes; for other tubes they are a guide in the dimensionless settings (h/t, n_t,
!! particle aspect ratio), not a guarantee.
module mpm_advice
  use mpm_kinds, only: wp
  use mpm_constants, only: SHAPE_RING, SHAPE_TUBE, SECTOR_FULL, SECTOR_QUARTER, basis_names, &
                           scheme_names, PLANE_STRESS, SCHEME_USL, SCHEME_MUSL, BASIS_LINEAR, &
                           BASIS_UGIMP, &
                           BASIS_CPDI2, MODEL_NEOHOOKEAN, &
                           VOLUMETRIC_FBAR, VOLUMETRIC_STANDARD, VOLUMETRIC_FBARWALL, &
                           volumetric_names, pi, CONTACT_STICK, CONTACT_BONDED, SHAPE_FILLER
  use mpm_particles, only: ring_counts
  use mpm_bodies, only: body_wall_thickness, is_section, bodies_wall_ppc, body_section, body_low
  use mpm_sections, only: section_t
  use mpm_config_types, only: config_t, scene_of, stiffest_penalty
  use mpm_walls, only: wall_t, wall_travel
  use mpm_time_step, only: cfl_study, cfl_margin, ppc_low, cfl_tried_min
  use mpm_errors, only: append_msg
  use mpm_units, only: advice_units
  use mpm_strings, only: rtoa, itoa, sci
  implicit none
  private

  public :: advice_check, advice_end_of_run, wall_too_thin
  public :: cfl_text, cfl_why
  ! (for mpm_study_advice)
  public :: ring_resolution, advice_stability, ring_aspect, approach_speed, volumetric_fits, &
            pct_text

  !> A row of the stability table: the largest cfl at which the impact scene completes, at 2
  !! and at 1 particle per cell through the wall (0: at none tried).
  type :: limit_row_t
    character(len=8) :: basis = '', scheme = ''
    real(wp) :: completes(2) = 0.0_wp
  end type limit_row_t

  include 'mpm_stability_table.inc'

  real(wp), parameter :: flip_trusted = 0.999_wp   !! flip below this dissipates visibly [-]
  real(wp), parameter :: delta_fold = 0.8_wp       !! delta/D from which CPDI domains fold [-]
  !> The platens' approach speed over D omega_2 (the ring's ovalling mode) above which the
  !! crush is not quasi-static: the study's steel crush (D omega_2 = 505 m/s) is 8 % from the
  !! static finite element curve at 10 m/s (0.020), 3.1 % at 5 m/s (0.0099) and 2.3 % at 2.5
  !! (the resolution's own error): inertia adds about 6 % at 0.020 and 1 % at 0.010
  real(wp), parameter :: quasi_static_ratio = 0.012_wp
  !> The same for a 'tube' section against H omega_1, H its height along the
  !! platen's normal and omega_1 = pi^2 sqrt(E' I / (m L^4)) its longest wall's first bending
  !! mode, pinned at its ends: the steel square tube (namelists/sections/square_tube.nml, H omega_1
  !! = 527 m/s) is 2.3 % from the static finite element curve at 2 m/s (0.0038), 10.6 % at 4 m/s
  !! (0.0076) and 47 % at 8 m/s (docs/validation.md#quasi-static)
  real(wp), parameter :: quasi_static_section = 0.005_wp

  !> volumetric = 'fbarwall' is measured good at n_thick = 4 (h = t/4 and t/2) and too soft at
  !! 8 (docs/validation.md); above this n_thick --check warns [-]
  integer, parameter :: fbarwall_nt_max = 5
  !> ... and with about square particles: outside this particle aspect --check warns [-]
  real(wp), parameter :: fbarwall_aspect_lo = 0.8_wp, fbarwall_aspect_hi = 1.25_wp
  !> Where each warning's evidence is (the doc sections the warnings end with)
  character(len=*), parameter :: doc_seams = 'docs/method.md#self-contact'
  character(len=*), parameter :: doc_thin = 'docs/stability.md#thin-walls', &
    doc_ppc = 'docs/stability.md#particles', &
    doc_spacing = 'docs/validation.md#spacing', &
    doc_volumetric = 'docs/validation.md#locking', &
    doc_schemes = 'docs/stability.md#schemes', doc_bases = 'docs/stability.md#bases', &
    doc_fold = 'docs/stability.md#full-crush', &
    doc_self_contact = 'docs/method.md#self-contact', &
    doc_quasi_static = 'docs/validation.md#quasi-static', &
    doc_energy = 'docs/stability.md#energy', doc_cfl = 'docs/stability.md#the-automatic-cfl', &
    doc_filler = 'docs/method.md#sections'

contains

  !> The n_thick that gives two particles per cell through a wall of thickness t [-]
  pure integer function n_thick_for(h, t) result(nt)
    real(wp), intent(in) :: h              !! cell size [m]
    real(wp), intent(in) :: t              !! wall thickness [m]
    nt = max(2, ceiling(2.0_wp*t/h - 1.0e-9_wp))
  end function n_thick_for

  !> The thickness of the thinnest wall of the case's rings and sections (0 without) [m]
  pure real(wp) function ring_t(cfg) result(t)
    type(config_t), intent(in) :: cfg      !! the case
    integer :: ib
    t = 0.0_wp
    do ib = 1, size(cfg%bodies)            ! rings and the walls of sections
      if (body_wall_thickness(cfg%bodies(ib)) <= 0.0_wp) cycle
      if (t == 0.0_wp .or. body_wall_thickness(cfg%bodies(ib)) < t) &
        t = body_wall_thickness(cfg%bodies(ib))
    end do
  end function ring_t

  !> Whether cells of size h are too coarse for a wall of thickness t: both faces of the wall
  !! share grid nodes (docs/stability.md).
  pure logical function wall_too_thin(h, t)
    real(wp), intent(in) :: h   !! cell size [m]
    real(wp), intent(in) :: t   !! wall thickness [m]
    wall_too_thin = h >= t
  end function wall_too_thin

  !> The most (largest = .true.) or the fewest particles through the wall of any ring body
  !! (0 without rings).
  pure integer function ring_n_thick(cfg, largest) result(nt)
    type(config_t), intent(in) :: cfg      !! the case
    logical, intent(in) :: largest         !! the largest n_thick, else the smallest
    logical :: ring(size(cfg%bodies))
    ring = cfg%bodies%shape_id == SHAPE_RING
    nt = 0
    if (.not. any(ring)) return
    if (largest) then
      nt = maxval(cfg%bodies%n_thick, mask=ring)
    else
      nt = minval(cfg%bodies%n_thick, mask=ring)
    end if
  end function ring_n_thick

  !> A ring's particle aspect ratio: length around the wall over length through it, with the
  !! particles around the whole ring as the set-up makes them (n_circ = 0: automatic).
  pure real(wp) function ring_aspect(cfg, ib) result(aspect)
    type(config_t), intent(in) :: cfg      !! the case
    integer, intent(in) :: ib              !! a ring body
    integer :: nfull, npb, ncb
    associate (b => cfg%bodies(ib))
      call ring_counts(b%r_inner, b%r_outer, b%n_thick, b%n_circ, SECTOR_FULL, nfull, npb, ncb)
      aspect = (pi*(b%r_inner + b%r_outer)/real(nfull, wp))/ &
               ((b%r_outer - b%r_inner)/real(b%n_thick, wp))
    end associate
  end function ring_aspect

  !> The automatic cfl and why, in one line (--check's report): the stability study's limit
  !! times the margin, the accuracy limit, or the fallback where no study ran the method.
  function cfl_why(cfg, cfl) result(why)
    type(config_t), intent(in) :: cfg      !! the case
    real(wp), intent(in) :: cfl            !! the automatic cfl in use [-]
    character(len=:), allocatable :: why
    real(wp) :: ppc, limit, accurate, base
    character(len=160) :: density
    character(len=16) :: c_margin, c_ppc, c_pen
    character(len=:), allocatable :: method
    logical :: known
    ppc = bodies_wall_ppc(cfg%bodies, cfg%grid%h)
    call cfl_study(cfg%solver%basis_id, cfg%solver%scheme_id, ppc, limit, accurate, known)
    write(c_ppc, '(f9.2)') ppc
    if (ppc < ppc_low) then
      density = 'at 1 particle per cell through the wall (this input: '// &
        trim(adjustl(c_ppc))//' < 1.5)'
    else if (ppc < huge(1.0_wp)) then
      density = 'at 2 particles per cell through the wall (this input: '// &
        trim(adjustl(c_ppc))//' >= 1.5)'
    else
      density = 'at 2 particles per cell through the wall (the input has no ring)'
    end if
    write(c_margin, '(f4.2)') cfl_margin
    method = 'basis '''//trim(basis_names(cfg%solver%basis_id))//''' with scheme '''// &
             trim(scheme_names(cfg%solver%scheme_id))//''''
    base = cfl_margin*cfl_tried_min
    if (limit > 0.0_wp) base = cfl_margin*limit
    if (.not. known) then
      why = cfl_text(cfl)//', automatic (cfl = 0): '//trim(c_margin)//' x '// &
        cfl_text(cfl_tried_min)//', the smallest cfl the stability study tried: it has not '// &
        'run '//method//' yet (make stability; docs/stability.md)'
    else if (scene_of(cfg) /= 'crush' .and. accurate > 0.0_wp .and. accurate < base) then
      why = cfl_text(cfl)//', automatic (cfl = 0): the largest cfl at which '//method// &
        ' kept an elastic impact''s energy within 1 % '//trim(density)// &
        ' (docs/stability.md#the-automatic-cfl)'
    else if (limit > 0.0_wp) then
      why = cfl_text(cfl)//', automatic (cfl = 0): '//trim(c_margin)//' x '// &
        cfl_text(limit)//', the largest cfl at which the stability study found '// &
        method//' stable '//trim(density)//' (docs/stability.md)'
    else
      why = cfl_text(cfl)//', automatic (cfl = 0): '//trim(c_margin)//' x '// &
        cfl_text(cfl_tried_min)//', the smallest cfl the stability study tried; it found '// &
        method//' stable at no cfl '//trim(density)//' (docs/stability.md)'
    end if
    write(c_pen, '(f5.2)') stiffest_penalty(cfg)
    if (stiffest_penalty(cfg) > 1.0_wp) why = why//', divided by the largest '// &
      '&wall penalty, '//trim(adjustl(c_pen))
  end function cfl_why

  !> Append a warning line; 'body 1: ' is left out when the case has a single body.
  pure subroutine add_line(cfg, warnings, line)
    type(config_t), intent(in) :: cfg      !! the case
    character(len=:), allocatable, intent(inout) :: warnings  !! lines so far
    character(len=*), intent(in) :: line   !! the warning
    if (size(cfg%bodies) == 1 .and. index(line, 'body 1: ') == 1) then
      call append_msg(warnings, line(9:))
    else
      call append_msg(warnings, line)
    end if
  end subroutine add_line

  !> A cfl as text with up to four decimals ('1.9', '0.3125').
  pure function cfl_short(cfl) result(str)
    real(wp), intent(in) :: cfl            !! a cfl number [-]
    character(len=:), allocatable :: str
    str = cfl_text(cfl)
    str = str(1:min(len(str), index(str, '.') + 4))
    do while (str(len(str):len(str)) == '0' .and. str(len(str) - 1:len(str) - 1) /= '.')
      str = str(1:len(str) - 1)
    end do
  end function cfl_short

  !> A cfl as text with six decimals (the study's limits are multiples of 1/32, exact here).
  pure function cfl_text(cfl) result(str)
    real(wp), intent(in) :: cfl            !! a cfl number [-]
    character(len=:), allocatable :: str
    character(len=16) :: buf
    write(buf, '(f9.6)') cfl
    str = trim(adjustl(buf))
  end function cfl_text

  !> The warnings a mechanics expert would give about the set-up, one per line ('' none):
  !! resolution of the wall, quasi-static crushing, the fixed time step, and where the
  !! stability study found the method failing.
  subroutine advice_check(cfg, h, c_max, vmax, dt, walls, warnings)
    type(config_t), intent(in) :: cfg      !! the case
    real(wp), intent(in) :: h              !! cell size of the set-up [m]
    real(wp), intent(in) :: c_max          !! largest wave speed [m/s]
    real(wp), intent(in) :: vmax           !! largest initial speed [m/s]
    real(wp), intent(in) :: dt             !! time step in use [s]
    type(wall_t), intent(in) :: walls(:)   !! the set-up's walls, mirror planes included
    character(len=:), allocatable, intent(out) :: warnings  !! warnings, one per line ('' none)
    character(len=512) :: line
    warnings = ''
    if (.not. cfg%run%check_units) call advice_units(cfg, warnings)  ! (else refused at input)
    call advice_walls(cfg, walls, warnings)
    if (cfg%run%dt > 0.0_wp .and. cfg%run%dt > 0.3_wp*h/(c_max + vmax)) then
      line = 'dt = '//sci(cfg%run%dt, 3)//' s is cfl '//cfl_short(cfg%run%dt*(c_max + vmax)/h)// &
        ' (> 0.3: may go unstable). Set dt = 0 ('//doc_cfl//')'
      call add_line(cfg, warnings, line)
    end if
    call advice_stability(cfg, dt*(c_max + vmax)/h, warnings)
    call advice_full_crush(cfg, walls, warnings)
    call advice_seams(cfg, warnings)
    call advice_filler(cfg, h, dt*(c_max + vmax)/h, warnings)
  end subroutine advice_check

  !> A filler that touches its tube (fill_gap below h/2) with basis 'ugimp': the squares of
  !! the tube's and the filler's particles overlap at t = 0, and their contact went unstable
  !! at the automatic cfl (0.86 with 'musl'; a half square tube filled with foam,
  !! tests/test_scene_matrix.py's filler rows) and at 0.6: stable at cfl 0.4, with a gap of
  !! h/2, or with the CPDI bases, whose domains are the particles' own.
  subroutine advice_filler(cfg, h, cfl, warnings)
    type(config_t), intent(in) :: cfg
    real(wp), intent(in) :: h                !! cell size [m]
    real(wp), intent(in) :: cfl              !! the cfl in use [-]
    character(len=:), allocatable, intent(inout) :: warnings
    integer :: ib
    character(len=8) :: c_cfl
    if (cfg%solver%basis_id /= BASIS_UGIMP .or. .not. cfl > 0.4_wp) return
    do ib = 1, size(cfg%bodies)
      if (cfg%bodies(ib)%shape_id /= SHAPE_FILLER) cycle
      if (cfg%bodies(ib)%fill_gap >= 0.5_wp*h) cycle
      write(c_cfl, '(f5.2)') cfl
      call add_line(cfg, warnings, 'body '//itoa(ib)//': filler touching its tube with '// &
        '''ugimp'': unstable at cfl '//trim(adjustl(c_cfl))//'. Set cfl = 0.4 ('//doc_filler//')')
      exit
    end do
  end subroutine advice_filler

  !> Per ring body: cells against the wall thickness and particles through the wall
  !! (ring_resolution), and the platen speed against the ring's ovalling mode (inextensional
  !! in-plane mode n = 2 of a thin ring: omega_n^2 = E I n^2 (n^2 - 1)^2 / (rho A R^4 (n^2 + 1));
  !! Love 1927, Blevins 1979).
  subroutine advice_walls(cfg, walls, warnings)
    type(config_t), intent(in) :: cfg
    type(wall_t), intent(in) :: walls(:)   !! the walls, with the mirror planes
    character(len=:), allocatable, intent(inout) :: warnings
    integer :: ib, k, worst(size(cfg%walls))
    real(wp) :: t, rm, ei, mass, omega2, vwall, ratio, top(size(cfg%walls))
    character(len=512) :: line
    character(len=16) :: rtext
    character(len=:), allocatable :: which
    top = 0.0_wp                           ! per wall: the largest ratio over the rings
    rm = 0.0_wp
    omega2 = 0.0_wp
    worst = 0
    do ib = 1, size(cfg%bodies)
      associate (b => cfg%bodies(ib))
        if (is_section(b%shape_id)) call ring_resolution(cfg, ib, warnings)   ! as for rings
        ! (a 'tube' only: the calibration is the square tube's; a honeycomb's or a walls
        ! body's rows collapse one by one, a crush this measure was not tried on)
        if (b%shape_id /= SHAPE_RING .and. b%shape_id /= SHAPE_TUBE) cycle
        if (b%shape_id == SHAPE_RING) then
          t = b%r_outer - b%r_inner
          call ring_resolution(cfg, ib, warnings)
          ! quasi-static crushing: platen speed against the ovalling mode (Love 1927, n = 2)
          rm = 0.5_wp*(b%r_inner + b%r_outer)
          associate (m => cfg%materials(b%material_id))
            ei = m%E*t**3/12.0_wp
            if (cfg%solver%plane_id /= PLANE_STRESS) ei = ei/(1.0_wp - m%nu**2)
            mass = m%rho*cfg%solver%mass_scale*t
            omega2 = sqrt(ei/(mass*rm**4)*4.0_wp*9.0_wp/5.0_wp)
          end associate
        end if
        do k = 1, size(cfg%walls)
          vwall = abs(dot_product(cfg%walls(k)%velocity, cfg%walls(k)%normal))
          if (vwall <= 0.0_wp .or. cfg%walls(k)%n_motion > 0 .or. cfg%walls(k)%mass > 0.0_wp) &
            cycle
          if (b%shape_id == SHAPE_RING) then                  ! the platens' approach
            ratio = approach_speed(walls)/(omega2*2.0_wp*rm)
          else                                                ! on the section's scale
            ratio = approach_speed(walls)/section_speed(cfg, ib, cfg%walls(k)%normal)* &
                    (quasi_static_ratio/quasi_static_section)
          end if
          if (ratio > top(k)) then
            top(k) = ratio
            worst(k) = ib
          end if
        end do
      end associate
    end do
    do k = 1, size(cfg%walls)              ! the first moving wall, for the worst ring
      if (.not. top(k) > quasi_static_ratio) cycle
      vwall = abs(dot_product(cfg%walls(k)%velocity, cfg%walls(k)%normal))
      which = ''
      if (count(cfg%bodies%shape_id == SHAPE_RING .or. cfg%bodies%shape_id == SHAPE_TUBE) > 1) &
        which = ' of body '//itoa(worst(k))
      if (cfg%bodies(worst(k))%shape_id == SHAPE_RING) then
        write(rtext, '(f5.3)') top(k)
        if (top(k) >= 9.9995_wp) rtext = sci(top(k), 2)         ! (no field overflow)
        write(line, '(a,i0,a)') 'wall ', k, ': not quasi-static ('//trim(rtext)// &
          ' D omega_2'//which//'). Set |velocity| <= '// &
          sci(quasi_static_ratio*vwall/top(k), 1)//' ('//doc_quasi_static//')'
      else
        write(rtext, '(f6.4)') top(k)*quasi_static_section/quasi_static_ratio
        if (top(k)*quasi_static_section/quasi_static_ratio >= 9.99995_wp) &
          rtext = sci(top(k)*quasi_static_section/quasi_static_ratio, 2)
        write(line, '(a,i0,a)') 'wall ', k, ': not quasi-static ('//trim(rtext)// &
          ' H omega_1'//which//'). Set |velocity| <= '// &
          sci(quasi_static_ratio*vwall/top(k), 1)//' ('//doc_quasi_static//')'
      end if
      call add_line(cfg, warnings, line)
      exit
    end do
  end subroutine advice_walls

  !> The resolution of ring body ib: cells against the wall thickness, particles through the
  !! wall, and the refinement study's error at h between t/4 and t/2.
  subroutine ring_resolution(cfg, ib, warnings)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: ib                !! a ring body, or a section (its thinnest wall)
    character(len=:), allocatable, intent(inout) :: warnings
    real(wp) :: t
    character(len=512) :: line
    associate (b => cfg%bodies(ib))
      t = body_wall_thickness(b)
      if (wall_too_thin(cfg%grid%h, t)) then
        write(line, '(a,i0,a)') 'body ', ib, ': h >= wall t = '//sci(t, 2)//' m. Set h = '// &
          sci(0.25_wp*t, 2)//', n_thick = 8 ('//doc_thin//')'
        call add_line(cfg, warnings, line)
      else if (cfg%grid%h > 0.5_wp*t*(1.0_wp + 1.0e-9_wp)) then
        write(line, '(a,i0,a,f4.2,a)') 'body ', ib, ': h/t = ', cfg%grid%h/t, &
          ': crush force 7-25 % high. Set h = '//sci(0.25_wp*t, 2)//', n_thick = 8 ('// &
          doc_thin//')'
        call add_line(cfg, warnings, line)
      end if
      if (b%n_thick <= 2) then
        write(line, '(a,i0,a,i0,a)') 'body ', ib, ': n_thick = ', b%n_thick, &
          ' locks the wall (crush x1.6-2.7). Set n_thick = '// &
          itoa(max(4, n_thick_for(cfg%grid%h, t)))//' ('//doc_ppc//')'
        call add_line(cfg, warnings, line)
      end if
      ! (from 1.045 t/4: the study's h = t/4 settings were run up to h x 1.04, the crush's 2 %
      ! setting 1.60 % there; 'fbarwall' at h = t/2, n_thick = 4, once excepted as the crush's
      ! 5 % setting, is 3.5 % on the study's grid but 7.4 % on one 3 % finer)
      if (cfg%grid%h > 1.045_wp*0.25_wp*t .and. cfg%grid%h <= 0.5_wp*t*(1.0_wp + 1.0e-9_wp)) then
        write(line, '(a,i0,a,f4.2,a)') 'body ', ib, ': h/t = ', cfg%grid%h/t, &
          ': crush 10-12 %, impact 26-29 % off. Set h = '// &
          sci(0.25_wp*t, 2)//', n_thick = 8 ('//doc_spacing//')'
        call add_line(cfg, warnings, line)
      end if
    end associate
  end subroutine ring_resolution

  !> A section's self-contact seams (welded joints) pressed on a 'stick' or 'bonded' wall
  !! with a basis of squares: the weld mixes a stuck field with a free one, which went
  !! unstable (basis 'ugimp', a multi-cell tube's T joint on a 'stick' platen).
  subroutine advice_seams(cfg, warnings)
    type(config_t), intent(in) :: cfg
    character(len=:), allocatable, intent(inout) :: warnings
    integer :: ib
    if (cfg%solver%basis_id /= BASIS_UGIMP .and. cfg%solver%basis_id /= BASIS_LINEAR) return
    if (.not. any(cfg%walls%contact_id == CONTACT_STICK .or. &
                  cfg%walls%contact_id == CONTACT_BONDED)) return
    do ib = 1, size(cfg%bodies)
      if (.not. (cfg%bodies(ib)%self_contact .and. is_section(cfg%bodies(ib)%shape_id))) cycle
      call add_line(cfg, warnings, 'body '//itoa(ib)//': joints on a stick/bonded wall may go '// &
        'unstable with '''//trim(basis_names(cfg%solver%basis_id))//'''. Set basis = '// &
        '''cpdi2'' ('//doc_seams//')')
    end do
  end subroutine advice_seams

  !> Where the stability study (docs/stability.md, tools/stability.py) found the method
  !! failing: particles per cell through the wall, cfl against the measured limit for the
  !! scheme and basis (src/advice/mpm_stability_table.inc), USL, linear weights, PIC blending.
  subroutine advice_stability(cfg, cfl, warnings)
    type(config_t), intent(in) :: cfg
    real(wp), intent(in) :: cfl              !! the cfl in use [-]
    character(len=:), allocatable, intent(inout) :: warnings
    real(wp) :: completes, ppc, flip, pen
    integer :: scheme, basis, k
    character(len=512) :: line
    character(len=32) :: flip_text
    logical :: wall_off
    scheme = cfg%solver%scheme_id
    basis = cfg%solver%basis_id
    flip = cfg%solver%flip
    ppc = bodies_wall_ppc(cfg%bodies, cfg%grid%h)   ! fewest particles per cell through a wall
    pen = stiffest_penalty(cfg)   ! a stiffer wall divides the limit (cfl_auto)
    completes = -1.0_wp                     ! the study's limit (-1: no study ran the method)
    do k = 1, size(limit_rows)
      if (basis < 1 .or. basis > size(basis_names) .or. scheme < 1 .or. &
          scheme > size(scheme_names)) exit
      if (limit_rows(k)%basis /= basis_names(basis) .or. &
          limit_rows(k)%scheme /= scheme_names(scheme)) cycle
      completes = limit_rows(k)%completes(merge(2, 1, ppc < ppc_low))
    end do
    ! 'fbarwall' through one or two layers is the standard treatment (a line through them is
    ! exact): the warnings of 'standard' apply then
    wall_off = cfg%solver%volumetric_id == VOLUMETRIC_FBARWALL .and. &
               ring_n_thick(cfg, .false.) <= 2
    if (ppc < 0.75_wp) then
      write(line, '(f4.2,a)') ppc, ' particles per cell through the wall '// &
        '(crush x2.4). Set n_thick = '// &
        itoa(n_thick_for(cfg%grid%h, ring_t(cfg)))//' ('//doc_ppc//')'
      call add_line(cfg, warnings, line)
    else if (ppc < ppc_low .and. cfg%solver%volumetric_id == VOLUMETRIC_FBAR) then
      write(line, '(f4.2,a)') ppc, ' particles/cell with ''fbar'': crush 9 % above FE. '// &
        'Set n_thick = '// &
        itoa(n_thick_for(cfg%grid%h, ring_t(cfg)))//' ('//doc_ppc//')'
      call add_line(cfg, warnings, line)
    else if (ppc < ppc_low .and. cfg%solver%volumetric_id == VOLUMETRIC_FBARWALL .and. &
             .not. wall_off) then
      write(line, '(f4.2,a)') ppc, ' particles/cell with ''fbarwall'': crush 6-9 % off. '// &
        'Set ''standard'', n_thick = '// &
        itoa(n_thick_for(cfg%grid%h, ring_t(cfg)))//' ('//doc_ppc//')'
      call add_line(cfg, warnings, line)
    else if (ppc < ppc_low) then
      write(line, '(f4.2,a)') ppc, ' particles per cell through the wall: crush +28-32 %. '// &
        'Set n_thick = '// &
        itoa(n_thick_for(cfg%grid%h, ring_t(cfg)))//' ('//doc_ppc//')'
      call add_line(cfg, warnings, line)
    end if
    if (wall_off) then
      write(line, '(a,i0,a)') '''fbarwall'' changes nothing with n_thick = ', &
        ring_n_thick(cfg, .false.), '. Set n_thick = 4 ('// &
        doc_volumetric//')'
      call add_line(cfg, warnings, line)
    else if (cfg%solver%volumetric_id == VOLUMETRIC_FBARWALL) then
      if (ring_n_thick(cfg, .true.) > fbarwall_nt_max) then
        write(line, '(a,i0,a)') '''fbarwall'' with n_thick = ', ring_n_thick(cfg, .true.), &
          ': crush 16 % low. Set volumetric = ''standard'' ('//doc_volumetric//')'
        call add_line(cfg, warnings, line)
      end if
      call fbarwall_aspect(cfg, warnings)
    end if
    ! (FLIP's slow energy gain at one particle per cell, once warned of here for CPDI above
    ! cfl 0.34, was the half ring's mirror plane's: the re-run study finds CPDI1 and CPDI2 with
    ! MUSL stable to 1.94-1.97 there; what is left, e.g. CPDI2 with USF failing at every cfl,
    ! is in the 1-per-cell table below)
    write(flip_text, '(g0.4)') flip
    if (completes == 0.0_wp) then
      call add_line(cfg, warnings, ''''//trim(basis_names(basis))//''' + '''// &
        trim(scheme_names(scheme))//''' failed at every cfl. Set scheme = ''musl'', n_thick = '// &
        itoa(n_thick_for(cfg%grid%h, ring_t(cfg)))//' ('//doc_schemes//')')
    else if (completes > 0.0_wp .and. cfl > completes/pen*(1.0_wp + 1.0e-9_wp)) then
      if (pen > 1.0_wp) then                 ! a stiffer wall: the limit over its penalty
        call add_line(cfg, warnings, 'cfl '//cfl_short(cfl)//' > '// &
          cfl_short(completes/pen)//', the limit over &wall penalty. Set cfl = 0 ('// &
          doc_cfl//')')
      else
        call add_line(cfg, warnings, 'cfl '//cfl_short(cfl)//' > '//cfl_short(completes)// &
          ', the limit of '''//trim(basis_names(basis))//''' + '''// &
          trim(scheme_names(scheme))//'''. Set cfl = 0 ('//doc_cfl//')')
      end if
    end if
    if (scheme == SCHEME_USL) call add_line(cfg, warnings, 'scheme ''usl'' loses 5-8 % of '// &
      'an impact''s energy. Set scheme = ''musl'' ('//doc_schemes//')')
    if (basis == BASIS_LINEAR) call add_line(cfg, warnings, 'basis ''linear'': '// &
      'cell-crossing noise in the wall force. Set basis = ''cpdi2'' ('//doc_bases//')')
    if (flip < flip_trusted) call add_line(cfg, warnings, 'flip = '//trim(adjustl(flip_text))// &
      ': PIC damps (49 % of an impact lost at 0.99). Set flip = 1 ('//doc_schemes//')')
  end subroutine advice_stability

  !> volumetric = 'fbarwall' with particles far from square: the study's crush at n_thick = 4
  !! came out 6.6-16 % from the finite element curve at aspect 0.5, 0.75, 1.5 and 2 against
  !! 3.5-6.0 % at 0.85 and 1 (docs/validation.md, "The line through the wall and the particles'
  !! shape"). Not called where 'fbarwall' acts as 'standard' (n_thick <= 2).
  subroutine fbarwall_aspect(cfg, warnings)
    type(config_t), intent(in) :: cfg
    character(len=:), allocatable, intent(inout) :: warnings
    character(len=512) :: line
    real(wp) :: aspect
    integer :: ib
    do ib = 1, size(cfg%bodies)
      if (cfg%bodies(ib)%shape_id /= SHAPE_RING) cycle
      aspect = ring_aspect(cfg, ib)
      if (aspect >= fbarwall_aspect_lo .and. aspect <= fbarwall_aspect_hi) cycle
      write(line, '(a,i0,a,f4.2,a)') 'body ', ib, ': aspect ', aspect, ' with '// &
        '''fbarwall'': crush 8-16 % off. Set n_circ = 0 ('//doc_volumetric//')'
      call add_line(cfg, warnings, line)
    end do
  end subroutine fbarwall_aspect

  !> Near full crush: the relative approach of the platens at t_end (the advance of every moving
  !! wall into the material, not the mirror planes, doubled where a mirror plane of a
  !! half/quarter model is parallel to it) against the ring diameter. Beyond delta/D = 0.8:
  !! CPDI2 domains can fold at the side hinges (CPDI1 cannot), and the inner walls meet, which
  !! one velocity field welds (self_contact; a quarter model meets its mirror image instead).
  subroutine advice_full_crush(cfg, walls, warnings)
    type(config_t), intent(in) :: cfg
    type(wall_t), intent(in) :: walls(:)
    character(len=:), allocatable, intent(inout) :: warnings
    real(wp) :: delta, travel, ratio
    integer :: k, m, ib
    character(len=640) :: line
    delta = 0.0_wp
    do k = 1, size(walls)
      if (walls(k)%mirror) cycle
      travel = -wall_travel(walls(k), cfg%run%t_end)   ! wall_travel is along -normal
      if (.not. travel > 0.0_wp) cycle
      do m = 1, size(walls)
        if (walls(m)%mirror .and. abs(dot_product(walls(m)%normal, walls(k)%normal)) &
            > 0.999_wp) travel = 2.0_wp*travel
      end do
      delta = delta + travel
    end do
    do ib = 1, size(cfg%bodies)
      associate (b => cfg%bodies(ib))
        if (b%shape_id == SHAPE_TUBE) call tube_solid(cfg, walls, ib, delta, warnings)
        if (b%shape_id /= SHAPE_RING) cycle
        ratio = max(0.0_wp, delta - platen_slack(cfg, walls, ib))/(2.0_wp*b%r_outer)
        if (.not. ratio > delta_fold) cycle
        if (cfg%solver%basis_id == BASIS_CPDI2) then
          write(line, '(a,i0,a,f4.2,a)') 'body ', ib, ': delta/D reaches ', ratio, &
            ': CPDI2 can fold. Set basis = ''cpdi1'' ('//doc_fold//')'
          call add_line(cfg, warnings, line)
        end if
        if (b%sector_id /= SECTOR_QUARTER .and. .not. b%self_contact) then
          write(line, '(a,i0,a,f4.2,a)') 'body ', ib, ': delta/D reaches ', ratio, &
            ': inner walls weld. Set self_contact = .true. ('//doc_self_contact//')'
          call add_line(cfg, warnings, line)
        end if
      end associate
    end do
  end subroutine advice_full_crush

  !> A 'tube' crushed flat: the platens' approach delta, less their gaps to the tube at t = 0,
  !! beyond its height along their normal less two walls (the two faces that meet) presses
  !! solid metal.
  subroutine tube_solid(cfg, walls, ib, delta, warnings)
    type(config_t), intent(in) :: cfg
    type(wall_t), intent(in) :: walls(:)
    integer, intent(in) :: ib
    real(wp), intent(in) :: delta                !! the platens' approach at t_end [m]
    character(len=:), allocatable, intent(inout) :: warnings
    real(wp) :: height, room, n(2)
    integer :: j, m
    associate (b => cfg%bodies(ib))
      j = first_moving(cfg, walls)
      if (j == 0 .or. b%n_vertices < 3) return
      n = walls(j)%normal                        ! the loading direction
      height = maxval([(dot_product(b%vertices(2*m-1:2*m), n), m = 1, b%n_vertices)]) - &
               minval([(dot_product(b%vertices(2*m-1:2*m), n), m = 1, b%n_vertices)]) + &
               b%thickness
      room = height - 2.0_wp*b%thickness
      if (.not. delta - platen_slack(cfg, walls, ib) > room) return
      call add_line(cfg, warnings, 'body '//itoa(ib)//': delta '// &
        sci(delta - platen_slack(cfg, walls, ib), 2)//' m > height - 2t, '//sci(room, 2)// &
        ' m. Set a smaller &wall stroke ('//doc_fold//')')
    end associate
  end subroutine tube_solid

  !> The first wall that moves into the material by t_end (not a mirror plane), 0 if none: the
  !! loading direction is its normal.
  pure integer function first_moving(cfg, walls) result(k)
    type(config_t), intent(in) :: cfg
    type(wall_t), intent(in) :: walls(:)
    do k = 1, size(walls)
      if (.not. walls(k)%mirror .and. -wall_travel(walls(k), cfg%run%t_end) > 0.0_wp) return
    end do
    k = 0
  end function first_moving

  !> How far the platens close before they squeeze body ib [m]: the gap between each moving
  !! wall and the body at t = 0 (doubled where a mirror plane parallel to the wall brings its
  !! image), and that of a fixed wall facing it (a tube nested in another, or lying off the
  !! platens, sees less than the platens' approach).
  pure real(wp) function platen_slack(cfg, walls, ib) result(slack)
    type(config_t), intent(in) :: cfg
    type(wall_t), intent(in) :: walls(:)
    integer, intent(in) :: ib
    real(wp) :: gap, fac, n(2)
    integer :: k, m, j
    logical :: moving
    slack = 0.0_wp
    k = first_moving(cfg, walls)
    if (k == 0) return
    n = walls(k)%normal
    do j = 1, size(walls)                  ! every platen along it, moving or fixed
      if (walls(j)%mirror .or. abs(dot_product(walls(j)%normal, n)) < 0.999_wp) cycle
      gap = max(0.0_wp, body_low(cfg%bodies(ib), walls(j)%normal) - &
                        dot_product(walls(j)%point0, walls(j)%normal))
      moving = -wall_travel(walls(j), cfg%run%t_end) > 0.0_wp
      fac = 1.0_wp
      do m = 1, size(walls)
        if (moving .and. walls(m)%mirror .and. abs(dot_product(walls(m)%normal, n)) > &
            0.999_wp) fac = 2.0_wp
      end do
      slack = slack + fac*gap
    end do
  end function platen_slack

  !> The end-of-run warning: the energy balance did not close ('' when it did). The error is
  !! judged against the growth check's scale, so that the tiny work of a crush's first steps
  !! does not count.
  function advice_end_of_run(bal_max, scale, energy_error, musl_flip, bodies) result(text)
    real(wp), intent(in) :: bal_max        !! largest energy balance error of the run [J]
    real(wp), intent(in) :: scale          !! max(initial energy, external work, floor) [J]
    real(wp), intent(in) :: energy_error   !! relative energy error at the end [-]
    logical, intent(in) :: musl_flip       !! the run used scheme = 'musl' and flip = 1
    logical, intent(in) :: bodies          !! bodies in contact (several velocity fields)
    character(len=:), allocatable :: text
    character(len=24) :: pct
    text = ''
    if (.not. bal_max > 0.05_wp*scale) return
    if (100.0_wp*energy_error < 1.0e6_wp) then
      pct = pct_text(energy_error)
    else
      pct = rtoa(100.0_wp*energy_error)
    end if
    text = 'energy error '//trim(pct)//' % > 5 %'
    if (bodies) then
      text = text//' (body contact incl.). Set '
    else
      text = text//': results in doubt. Set '
    end if
    if (musl_flip) then
      text = text//'a smaller h or cfl ('//doc_energy//')'
    else
      text = text//'scheme = ''musl'', flip = 1 ('//doc_energy//')'
    end if
  end function advice_end_of_run

  !> H omega_1 of section body ib [m/s]: H its height along `normal` (its walls' extent plus a
  !! wall thickness), omega_1 = pi^2 sqrt(E' I / (m L^4)) the first bending mode of its longest
  !! wall (the edges of one logical wall summed; L over the centreline), pinned at both ends,
  !! of that wall's thickness t (I = t^3 / 12, E' = E / (1 - nu^2) in plane strain, m = rho
  !! mass_scale t).
  function section_speed(cfg, ib, normal) result(speed)
    type(config_t), intent(in) :: cfg      !! the case
    integer, intent(in) :: ib              !! a section body
    real(wp), intent(in) :: normal(2)      !! the platen's normal [-]
    real(wp) :: speed
    type(section_t) :: s
    real(wp), allocatable :: len_w(:)
    real(wp) :: u(2), lo, hi, h, t, ei, mass, omega
    integer :: e, w
    call body_section(cfg%bodies(ib), s)
    speed = huge(1.0_wp)
    if (s%ne == 0) return
    allocate(len_w(maxval(s%ew)))
    len_w = 0.0_wp
    do e = 1, s%ne
      len_w(s%ew(e)) = len_w(s%ew(e)) + norm2(s%xn(:, s%en(2, e)) - s%xn(:, s%en(1, e)))
    end do
    w = maxloc(len_w, 1)
    t = maxval(s%et, mask=s%ew == w)
    u = normal/norm2(normal)
    lo = minval(matmul(u, s%xn(:, 1:s%nn)))
    hi = maxval(matmul(u, s%xn(:, 1:s%nn)))
    h = hi - lo + t
    associate (m => cfg%materials(cfg%bodies(ib)%material_id))
      ei = m%E*t**3/12.0_wp
      if (cfg%solver%plane_id /= PLANE_STRESS) ei = ei/(1.0_wp - m%nu**2)
      mass = m%rho*cfg%solver%mass_scale*t
    end associate
    omega = pi**2*sqrt(ei/(mass*len_w(w)**4))
    speed = h*omega
  end function section_speed

  !> The relative approach speed of the platens [m/s]: the normal speed of every moving wall
  !! (its prescribed velocity, before any ramp or motion table), doubled where a mirror plane of
  !! a half/quarter model is parallel to it (the image platen approaches too), as
  !! advice_full_crush counts the travel.
  pure real(wp) function approach_speed(walls) result(v)
    type(wall_t), intent(in) :: walls(:)  !! the walls, with the mirror planes
    real(wp) :: vk
    integer :: k, m
    v = 0.0_wp
    do k = 1, size(walls)
      if (walls(k)%mirror) cycle
      vk = abs(dot_product(walls(k)%velocity, walls(k)%normal))
      do m = 1, size(walls)
        if (walls(m)%mirror .and. abs(dot_product(walls(m)%normal, walls(k)%normal)) &
            > 0.999_wp) vk = 2.0_wp*vk
      end do
      v = v + vk
    end do
  end function approach_speed

  !> Whether the input could take volumetric = 'fbar' or 'fbarwall' at all (the rule is
  !! mpm_config_check's, which refuses them otherwise): one velocity field (one body, no
  !! self_contact), plane strain, no neohookean material, rings only for 'fbarwall' (both
  !! treatments are asked for together: the study's runs of either are advised only where both
  !! fit, which for its ring scenes is the same).
  pure logical function volumetric_fits(cfg) result(fits)
    type(config_t), intent(in) :: cfg     !! the case
    fits = size(cfg%bodies) == 1 .and. cfg%solver%plane_id /= PLANE_STRESS
    if (.not. fits) return
    fits = .not. (cfg%bodies(1)%self_contact .or. cfg%bodies(1)%shape_id /= SHAPE_RING .or. &
                  any(cfg%materials%model_id == MODEL_NEOHOOKEAN))
  end function volumetric_fits

  !> A fraction as a percentage with two decimals and its leading zero ('0.79', '13.23').
  pure function pct_text(x) result(text)
    real(wp), intent(in) :: x              !! fraction [-]
    character(len=:), allocatable :: text
    character(len=32) :: buf
    write(buf, '(f0.2)') 100*x
    text = trim(adjustl(buf))
    if (text(1:1) == '.') text = '0'//text
  end function pct_text

end module mpm_advice
