!> What the refinement study (docs/validation.md) says about an input, for `tubempm --check`:
!! the cheapest settings the study found for 5 %, 2 % and 1 % error in the same kind of scene
!! (leaving out those --check's own warnings condemn), and the error of the study run nearest to
!! the input's resolution. The study's runs are compiled in from src/advice/mpm_advice_table.inc
!! (tools/advice_tables.py writes it from docs/study/study_full.csv); their rows are found by the
!! names of the basis and scheme. The errors hold for the study's scenes; for other tubes they
!! are a guide in the dimensionless settings (h/t, n_t, particle aspect ratio).
! SPDX-License-Identifier: MIT
module mpm_study_advice
  use mpm_kinds, only: wp
  use mpm_constants, only: SHAPE_RING, SCHEME_MUSL, CONTACT_SLIP, VOLUMETRIC_STANDARD, &
                           basis_names, &
                           volumetric_names, pi
  use mpm_config_types, only: config_t, scene_of, stiffest_penalty
  use mpm_walls, only: wall_t
  use mpm_errors, only: append_msg
  use mpm_strings, only: itoa
  use mpm_advice, only: ring_resolution, advice_stability, ring_aspect, approach_speed, &
                        volumetric_fits, pct_text
  implicit none
  private
  public :: study_advice

  include 'mpm_advice_table.inc'

contains

  !> Whether --check's own warnings condemn study run i as advice for ring body ib of the
  !! input: the body alone with the run's settings (h = h/t t, n_thick, basis, cfl; MUSL and
  !! FLIP, as the study ran) would be warned of by ring_resolution or advice_stability. So the
  !! advice never recommends what the warnings condemn (the wave scene's 5 % run at n_thick = 2
  !! is not advised: at h = t/4 it has half a particle per cell through the wall).
  logical function study_condemned(cfg, ib, i) result(condemned)
    type(config_t), intent(in) :: cfg     !! the case
    integer, intent(in) :: ib             !! its (first) ring body
    integer, intent(in) :: i              !! a run of the study table
    type(config_t) :: c
    character(len=:), allocatable :: w
    real(wp) :: t
    condemned = .true.
    if (study_volumetric(i) /= 'standard' .and. .not. volumetric_fits(cfg)) return
    c = cfg
    c%bodies = cfg%bodies(ib:ib)
    t = cfg%bodies(ib)%r_outer - cfg%bodies(ib)%r_inner
    c%grid%h = study_h_over_t(i)*t
    c%bodies(1)%n_thick = study_n_t(i)
    ! the study run's particles around the whole ring (its aspect), a multiple of 4
    c%bodies(1)%n_circ = max(4, 4*nint(pi*(cfg%bodies(ib)%r_inner + &
      cfg%bodies(ib)%r_outer)*real(study_n_t(i), wp)/(study_aspect(i)*t)/4.0_wp))
    c%solver%basis_id = findloc(basis_names, study_basis(i), dim=1)
    c%solver%scheme_id = SCHEME_MUSL
    c%solver%flip = 1.0_wp
    c%solver%volumetric_id = findloc(volumetric_names, study_volumetric(i), dim=1)
    c%run%cfl = study_cfl(i)
    where (c%walls%contact_id /= CONTACT_SLIP) c%walls%penalty = study_penalty(i)
    w = ''
    call ring_resolution(c, 1, w)
    call advice_stability(c, study_cfl(i), w)
    condemned = len(w) > 0
  end function study_condemned

  !> The advice as text lines (empty when the case is not one of the study's kinds).
  subroutine study_advice(cfg, h, cfl, walls, text)
    type(config_t), intent(in) :: cfg     !! the case
    real(wp), intent(in) :: h             !! grid spacing of the set-up [m]
    real(wp), intent(in) :: cfl           !! the cfl in use (given or automatic) [-]
    type(wall_t), intent(in) :: walls(:)  !! its walls, with the mirror planes of a sector
    character(len=:), allocatable, intent(out) :: text  !! lines, '' when no advice applies
    character(len=6) :: scene, basis
    character(len=8) :: volumetric
    character(len=400) :: line
    real(wp) :: t, hot, aspect, d, dbest, v, pin
    integer :: ib, k, i, j, best, nt
    text = ''
    pin = stiffest_penalty(cfg)   ! the stiffest wall's penalty
    scene = scene_of(cfg)
    if (len_trim(scene) == 0 .or. n_study == 0) return
    ib = 0                        ! the coarsest ring: largest h/t, then fewest particles through
    t = huge(1.0_wp)
    nt = 0
    do j = 1, size(cfg%bodies)
      associate (b => cfg%bodies(j))
        if (b%shape_id /= SHAPE_RING) cycle
        if (b%r_outer - b%r_inner < t .or. (b%r_outer - b%r_inner == t .and. b%n_thick < nt)) then
          ib = j
          t = b%r_outer - b%r_inner
          nt = b%n_thick
        end if
      end associate
    end do
    aspect = ring_aspect(cfg, ib)
    hot = h/t
    basis = basis_names(cfg%solver%basis_id)
    volumetric = volumetric_names(max(cfg%solver%volumetric_id, VOLUMETRIC_STANDARD))
    call append_msg(text, 'refinement study (docs/validation.md), '//trim(scene)// &
      ' scene: cheapest settings found that --check does not warn of, with their CPU time '// &
      'on the study''s machine:')
    if (scene == 'crush' .and. study_crush_approach > 0.0_wp) then
      v = approach_speed(walls)
      write(line, '(a,f0.2,a)') '  (crush errors: F(delta) against a static finite element '// &
        'curve, the platens approaching at ', study_crush_approach, ' m/s'
      if (v > 1.5_wp*study_crush_approach) then
        write(line, '(a,f0.2,a)') trim(line)//'; this input''s at ', v, ' m/s adds inertia: '// &
          'at 10 m/s the study''s h = t/4 crush is 8 % from the static curve, at 2.5 m/s 2.3 %)'
        call append_msg(text, trim(line))
      else
        call append_msg(text, trim(line)//')')
      end if
    end if
    do k = 1, n_advice
      if (advice_scene(k) /= scene) cycle
      i = 0                       ! the cheapest run within the target that no warning condemns,
      do j = 1, n_study           ! of those measured on other grids too (plot_study advice)
        if (study_scene(j) /= scene .or. study_error(j) > advice_target(k)) cycle
        if (study_alignments(j) < 2) cycle
        if (study_condemned(cfg, ib, j)) cycle
        if (i == 0) then
          i = j
        else if (study_cpu_s(j) < study_cpu_s(i)) then
          i = j
        end if
      end do
      if (i == 0) then
        write(line, '(a,f4.1,a)') '  error <= ', 100*advice_target(k), ' %: none in the study'
      else
        write(line, '(a,f4.1,a,g0.3,a,i0,a,f4.2,a,a,a,f4.2,a,i0,a)') &
          '  error <= ', 100*advice_target(k), ' %: h/t ', study_h_over_t(i), ', n_thick ', &
          study_n_t(i), ', aspect ', study_aspect(i), ', ', trim(study_basis(i)), ', cfl ', &
          study_cfl(i), vol_text(study_volumetric(i))// &
          pen_text(study_penalty(i), pin /= 1.0_wp)//': ', &
          study_particles(i), &
          ' particles, '//cpu_text(study_cpu_s(i))//' CPU s ('//error_text(i)//')'
      end if
      call append_msg(text, trim(line))
    end do
    ! the nearest study run, by refinement ratios (and the same basis if there is one)
    best = 0
    dbest = huge(1.0_wp)
    do i = 1, n_study
      if (study_scene(i) /= scene) cycle
      d = abs(log(study_h_over_t(i)/hot)) + abs(log(real(study_n_t(i), wp)/real(nt, wp))) + &
          abs(log(study_aspect(i)/aspect)) + abs(log(study_cfl(i)/cfl))
      if (study_basis(i) /= basis) d = d + 10.0_wp
      if (study_volumetric(i) /= volumetric) d = d + 10.0_wp
      d = d + abs(log(study_penalty(i)/pin))
      if (d < dbest) then
        dbest = d
        best = i
      end if
    end do
    line = '  this input'
    if (count(cfg%bodies%shape_id == SHAPE_RING) > 1) line = '  this input (body '//itoa(ib)// &
      ', its coarsest ring)'
    write(line, '(a,a,g0.3,a,i0,a,f4.2,a,a,a,f4.2,a)') trim(line), ': h/t ', hot, ', n_thick ', &
      nt, ', aspect ', aspect, ', ', trim(basis), ', cfl ', cfl, vol_text(volumetric)// &
      pen_text(pin, .false.)
    call append_msg(text, trim(line))
    if (best > 0) then
      write(line, '(a,g0.3,a,i0,a,f4.2,a,a,a,f4.2,a)') '  nearest study run: h/t ', &
        study_h_over_t(best), ', n_thick ', study_n_t(best), ', aspect ', study_aspect(best), &
        ', ', trim(study_basis(best)), ', cfl ', study_cfl(best), &
        vol_text(study_volumetric(best))//pen_text(study_penalty(best), pin /= 1.0_wp)// &
        ': '// &
        error_text(best)
      if (dbest > 0.2_wp) line = trim(line)//' (not a close match: treat as a rough guide)'
      call append_msg(text, trim(line))
    end if
  end subroutine study_advice

  !> 'error 3.50 %' for study run i, or where it was run on other grids too (h x 0.97 and
  !! 1.03, some x 0.96 to 1.04; docs/validation.md) 'error 7.36 % on the worst of 3 grids
  !! (h within 3 %), 3.50 % as run'.
  function error_text(i) result(text)
    integer, intent(in) :: i               !! a study run
    character(len=:), allocatable :: text
    character(len=96) :: buf
    text = 'error '//pct_text(study_error(i))//' %'
    if (study_alignments(i) > 1) then
      write(buf, '(a,i0,a,i0,a)') ' on the worst of ', study_alignments(i), &
        ' grids (h within ', nint(100*study_h_spread(i)), ' %), '
      text = text//trim(buf)//' '//pct_text(study_error_run(i))//' % as run'
    end if
  end function error_text

  !> CPU seconds as the study quotes them: three digits below 100 s ('0.280', '24.1'), whole
  !! seconds above ('610', not '610.').
  pure function cpu_text(x) result(text)
    real(wp), intent(in) :: x              !! CPU time [s]
    character(len=:), allocatable :: text
    character(len=32) :: buf
    if (x >= 99.5_wp) then
      write(buf, '(i0)') nint(x)
    else
      write(buf, '(g0.3)') x
    end if
    text = trim(adjustl(buf))
  end function cpu_text

  !> ', fbar' for a study run or input with volumetric = 'fbar', '' for the standard treatment.
  pure function vol_text(volumetric) result(s)
    character(len=*), intent(in) :: volumetric  !! 'standard' or 'fbar'
    character(len=:), allocatable :: s
    s = ''
    if (trim(volumetric) /= 'standard') s = ', '//trim(volumetric)
  end function vol_text

  !> ', &wall penalty 4.0' for a wall penalty other than 1, or for any where the input's is not
  !! 1 (`named`), else ''.
  pure function pen_text(penalty, named) result(s)
    real(wp), intent(in) :: penalty        !! &wall penalty [-]
    logical, intent(in) :: named           !! name it even at 1
    character(len=:), allocatable :: s
    character(len=8) :: buf
    s = ''
    if (penalty == 1.0_wp .and. .not. named) return
    write(buf, '(f0.2)') penalty
    s = ', &wall penalty '//trim(buf)
  end function pen_text
end module mpm_study_advice
