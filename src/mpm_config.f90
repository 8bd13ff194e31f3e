!> The case description read from one namelist file: types, reading, validation, echo.
! SPDX-License-Identifier: MIT
!
! The namelist variables are locals of the per-group readers called by read_config (no global
! input state); they get their defaults, are read group by group, validated, and copied into
! config_t. Before reading, the file text is scanned once: it gives the line of every group and
! of every `name = value`, so that every message can say `file:line`, and it lets a failed read
! be diagnosed precisely (gfortran's own namelist messages often name the wrong token).
module mpm_config
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  use, intrinsic :: ieee_exceptions, only: ieee_overflow, ieee_get_halting_mode, &
                                           ieee_set_halting_mode, ieee_get_flag, ieee_set_flag
  use, intrinsic :: iso_fortran_env, only: iostat_end, iostat_eor
  use mpm_kinds, only: wp
  use mpm_constants, only: name_len, path_len, max_table, EXIT_INPUT, EXIT_IO, &
                           basis_names, scheme_names, plane_names, model_names, rate_law_names, &
                           shape_names, sector_names, contact_names, &
                           BASIS_CPDI2, SCHEME_MUSL, PLANE_STRAIN, MODEL_J2, RATE_NONE, &
                           RATE_COWPER_SYMONDS, SHAPE_RING, SHAPE_RECT, SECTOR_FULL, SECTOR_HALF, &
                           SECTOR_QUARTER, CONTACT_FRICTIONLESS, CONTACT_COULOMB
  use mpm_errors, only: append_msg
  implicit none
  private
  public :: config_t, run_cfg_t, solver_cfg_t, grid_cfg_t, material_cfg_t, body_cfg_t, &
            wall_cfg_t, probe_cfg_t
  public :: read_config, write_config, write_config_unit, default_config
  public :: unset_real

  !> &run
  type :: run_cfg_t
    character(len=name_len) :: title = ''          !! label of the case
    character(len=path_len) :: output_dir = ''     !! folder for all outputs
    real(wp) :: t_end = -1.0_wp                    !! simulated time [s]
    real(wp) :: cfl = 0.2_wp                       !! Courant number [-]
    real(wp) :: dt = 0.0_wp                        !! fixed time step if > 0 [s]
    real(wp) :: history_every = 0.0_wp             !! history interval [s]
    real(wp) :: snapshot_every = 0.0_wp            !! snapshot interval [s]
    real(wp) :: checkpoint_every = 0.0_wp          !! wall-clock checkpoint interval [s]
    real(wp) :: depth = 1.0_wp                     !! out-of-plane length [m]
    real(wp) :: gravity(2) = 0.0_wp                !! body acceleration [m/s^2]
    integer :: threads = 0                         !! OpenMP threads (0 = runtime default)
  end type run_cfg_t

  !> &solver
  type :: solver_cfg_t
    character(len=name_len) :: basis = 'cpdi2'     !! linear | ugimp | cpdi1 | cpdi2
    character(len=name_len) :: scheme = 'musl'     !! usl | usf | musl
    character(len=name_len) :: plane = 'strain'    !! strain | stress
    integer :: basis_id = 0, scheme_id = 0, plane_id = 0  !! codes of mpm_constants
    real(wp) :: flip = 1.0_wp                      !! FLIP fraction [-]
    real(wp) :: mass_scale = 1.0_wp                !! density multiplier [-]
    real(wp) :: damping = 0.0_wp                   !! mass-proportional damping [1/s]
    logical :: deterministic = .false.             !! thread-count independent results
  end type solver_cfg_t

  !> &grid
  type :: grid_cfg_t
    real(wp) :: h = -1.0_wp                        !! cell size [m]
    real(wp) :: lower(2) = 0.0_wp                  !! lower domain corner [m]
    real(wp) :: upper(2) = 0.0_wp                  !! upper domain corner [m]
    logical :: fitted = .true.                     !! lower/upper not given: fit to the scene
  end type grid_cfg_t

  !> &material (repeatable)
  type :: material_cfg_t
    character(len=name_len) :: name = ''           !! label used by &body
    character(len=name_len) :: model = 'j2'        !! elastic | neohookean | j2
    character(len=name_len) :: rate_law = 'none'   !! none | cowper_symonds
    integer :: model_id = 0, rate_law_id = 0       !! codes of mpm_constants
    real(wp) :: E = -1.0_wp                        !! Young's modulus [Pa]
    real(wp) :: nu = -1.0_wp                       !! Poisson's ratio [-]
    real(wp) :: rho = -1.0_wp                      !! density [kg/m^3]
    real(wp) :: sigma_y = -1.0_wp                  !! initial yield stress [Pa]
    real(wp) :: hardening = 0.0_wp                 !! linear isotropic hardening modulus [Pa]
    real(wp) :: cs_d = 40.4_wp                     !! Cowper-Symonds D [1/s]
    real(wp) :: cs_q = 5.0_wp                      !! Cowper-Symonds q [-]
  end type material_cfg_t

  !> &body (repeatable)
  type :: body_cfg_t
    character(len=name_len) :: shape = 'ring'      !! ring | rect
    character(len=name_len) :: material = ''       !! a &material name
    character(len=name_len) :: sector = 'full'     !! full | half | quarter
    integer :: shape_id = 0, material_id = 0, sector_id = 0  !! codes; material_id indexes materials
    real(wp) :: center(2) = 0.0_wp                 !! centre [m]
    real(wp) :: r_inner = -1.0_wp                  !! ring inner radius [m]
    real(wp) :: r_outer = -1.0_wp                  !! ring outer radius [m]
    integer :: n_thick = 16                        !! particles through the wall
    integer :: n_circ = 0                          !! particles around the whole ring
    real(wp) :: size(2) = -1.0_wp                  !! rectangle sides [m]
    integer :: n_x = 0, n_y = 0                    !! particles along the rectangle sides
    real(wp) :: velocity(2) = 0.0_wp               !! initial velocity [m/s]
  end type body_cfg_t

  !> &wall (repeatable)
  type :: wall_cfg_t
    real(wp) :: point(2) = 0.0_wp                  !! point on the plane at t = 0 [m]
    real(wp) :: normal(2) = 0.0_wp                 !! unit normal into the material side [-]
    character(len=name_len) :: contact = 'frictionless'  !! frictionless|coulomb|stick|slip
    integer :: contact_id = 0                      !! code of mpm_constants
    real(wp) :: friction = 0.0_wp                  !! Coulomb coefficient [-]
    real(wp) :: velocity(2) = 0.0_wp               !! prescribed velocity [m/s]
    real(wp) :: ramp = 0.0_wp                      !! smooth rise time of the velocity [s]
    integer :: n_motion = 0                        !! points in the motion table
    real(wp) :: motion_t(max_table) = 0.0_wp       !! table times [s]
    real(wp) :: motion_f(max_table) = 0.0_wp       !! table factors on velocity [-]
    logical :: mirror = .false.                    !! added by a body sector (not in the input)
  end type wall_cfg_t

  !> &probe (repeatable)
  type :: probe_cfg_t
    real(wp) :: point(2) = 0.0_wp                  !! the particle nearest at t = 0 is recorded [m]
  end type probe_cfg_t

  !> The whole case.
  type :: config_t
    character(len=path_len) :: file = ''           !! the namelist file read
    type(run_cfg_t) :: run
    type(solver_cfg_t) :: solver
    type(grid_cfg_t) :: grid
    type(material_cfg_t), allocatable :: materials(:)
    type(body_cfg_t), allocatable :: bodies(:)
    type(wall_cfg_t), allocatable :: walls(:)
    type(probe_cfg_t), allocatable :: probes(:)
  end type config_t


  !> Marks a required number that was not given (wall and probe points, normals in
  !! default_config); the other required numbers keep their type defaults (-1, 0).
  real(wp), parameter :: unset_real = huge(1.0_wp)

  ! ---------------------------------------------------------------- private machinery
  integer, parameter :: iunset = -huge(1)       ! integer "not given" sentinel
  integer, parameter :: long_len = 1024         ! namelist text buffers (longer than allowed)
  integer, parameter :: n_groups = 7
  character(len=*), parameter :: group_names(n_groups) = [character(len=8) :: &
    'run', 'solver', 'grid', 'material', 'body', 'wall', 'probe']
  logical, parameter :: group_repeatable(n_groups) = &
    [.false., .false., .false., .true., .true., .true., .true.]
  integer, parameter :: tk_word = 1, tk_string = 2, tk_equals = 3

  !> One namelist variable: name as documented, kind (r real, i integer, l logical,
  !! c text) and number of values.
  type :: var_info_t
    character(len=16) :: name = ''
    character(len=1) :: kind = 'r'
    integer :: n = 1
  end type var_info_t

  type :: text_line_t
    character(len=:), allocatable :: s
  end type text_line_t

  !> A token of a group's text: a word, a quoted text or '='.
  type :: token_t
    character(len=:), allocatable :: text
    integer :: line = 0
    integer :: kind = tk_word
    logical :: comma_comment = .false.   ! followed by ", ! comment" at the end of its line
  end type token_t

  !> `name = value ...` inside a group (or stray text when stray is true).
  type :: assign_t
    character(len=:), allocatable :: base    ! lower-case name without subscript
    character(len=:), allocatable :: sub     ! subscript text without parentheses, or ''
    character(len=:), allocatable :: value   ! the value tokens joined by ', '
    integer :: line = 0
    integer :: t1 = 1, t2 = 0                ! value tokens
    logical :: stray = .false.
  end type assign_t

  !> One occurrence of a group in the file.
  type :: occ_t
    character(len=:), allocatable :: group   ! lower case
    integer :: index = 0                     ! k-th occurrence of this group name
    integer :: line = 0, end_line = 0
    logical :: closed = .false.
    logical :: readable = .true.             ! false: structural error already reported
    logical :: read_ok = .false.             ! the namelist read succeeded
    logical :: ok = .true.                   ! read and validated without error
    integer :: n_tok = 0, n_asg = 0
    type(token_t), allocatable :: tok(:)
    type(assign_t), allocatable :: asg(:)
  end type occ_t

  type :: msg_t
    integer :: line = 0
    character(len=:), allocatable :: text
  end type msg_t

  !> Everything known about the file being read, and the messages so far.
  type :: reader_t
    character(len=:), allocatable :: file
    integer :: n_lines = 0, n_occ = 0, n_err = 0, n_warn = 0
    type(text_line_t), allocatable :: lines(:)
    type(occ_t), allocatable :: occ(:)
    type(msg_t), allocatable :: err(:), warn(:)
  end type reader_t

  !> Accumulates formatted output and the first write error.
  type :: writer_t
    integer :: unit = 0
    integer :: ios = 0
    character(len=512) :: iomsg = ''
  end type writer_t

contains

  ! ======================================================================== reading

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
    character(len=:), allocatable :: advice
    call ieee_get_halting_mode(ieee_overflow, halting)
    call ieee_get_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, .false.)
    call read_config_all(path, cfg, stat, errmsg, advice)
    call ieee_set_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, halting)
    if (present(warnings)) call move_alloc(advice, warnings)
  end subroutine read_config

  !> read_config without the floating-point mode handling.
  subroutine read_config_all(path, cfg, stat, errmsg, warnings)
    character(len=*), intent(in) :: path
    type(config_t), intent(out) :: cfg
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable, intent(out) :: warnings
    type(reader_t) :: rd
    integer :: u, ios, ios2, io, ig, k
    integer :: n_of(n_groups), first_of(n_groups)
    integer, allocatable :: occ_mat(:), occ_body(:)
    character(len=512) :: iomsg, iomsg2
    logical :: is_dir

    stat = 0
    errmsg = ''
    warnings = ''
    cfg%file = path
    rd%file = trim(path)
    allocate(rd%err(8), rd%warn(8), rd%occ(8), rd%lines(64))

    if (len_trim(path) == 0) then
      stat = EXIT_IO
      errmsg = 'no input file name given; give the path of a .nml file'
      return
    end if
    inquire(file=trim(path)//'/.', exist=is_dir, iostat=ios, iomsg=iomsg)
    if (ios == 0 .and. is_dir) then
      stat = EXIT_IO
      errmsg = trim(path)//': is a folder, not a namelist file; give the path of a .nml file'
      return
    end if
    open(newunit=u, file=path, status='old', action='read', form='formatted', &
         access='sequential', iostat=ios, iomsg=iomsg)
    if (ios /= 0) then
      stat = EXIT_IO
      errmsg = trim(path)//': cannot open the input file ('//trim(iomsg)// &
               '); check the file name and that the file is readable'
      return
    end if
    call load_lines(rd, u, ios, iomsg)
    if (ios /= 0) then
      stat = EXIT_IO
      errmsg = trim(path)//': cannot read the input file ('//trim(iomsg)//')'
      close(u, iostat=ios2, iomsg=iomsg2)
      return
    end if
    if (.not. has_content(rd)) then
      stat = EXIT_INPUT
      errmsg = trim(path)//': the file is empty (no namelist groups); required: &run, &grid, '// &
               'at least one &material and one &body (tubempm --defaults prints a template)'
      close(u, iostat=ios2, iomsg=iomsg2)
      return
    end if

    call scan_source(rd)
    call check_groups(rd, n_of, first_of)
    allocate(cfg%materials(n_of(4)), cfg%bodies(n_of(5)), cfg%walls(n_of(6)), &
             cfg%probes(n_of(7)))
    allocate(occ_mat(n_of(4)), occ_body(n_of(5)))
    do io = 1, rd%n_occ
      ig = group_id(rd%occ(io)%group)
      k = rd%occ(io)%index
      select case (ig)
      case (1)
        if (k == 1) call read_run(rd, io, u, cfg%run)
      case (2)
        if (k == 1) call read_solver(rd, io, u, cfg%solver)
      case (3)
        if (k == 1) call read_grid(rd, io, u, cfg%grid)
      case (4)
        occ_mat(k) = io
        call read_material(rd, io, u, cfg%materials(k))
      case (5)
        occ_body(k) = io
        call read_body(rd, io, u, cfg%bodies(k))
      case (6)
        call read_wall(rd, io, u, cfg%walls(k))
      case (7)
        call read_probe(rd, io, u, cfg%probes(k))
      end select
    end do
    close(u, iostat=ios, iomsg=iomsg)

    call cross_checks(rd, cfg, first_of, occ_mat, occ_body)

    if (rd%n_err > 0) then
      stat = EXIT_INPUT
      errmsg = join_msgs(rd%err, rd%n_err)
    end if
    warnings = join_msgs(rd%warn, rd%n_warn)
  end subroutine read_config_all

  !> All records of the file into rd%lines (any length).
  subroutine load_lines(rd, u, ios, iomsg)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: iomsg
    character(len=:), allocatable :: line
    type(text_line_t), allocatable :: tmp(:)
    do
      call read_record(u, line, ios, iomsg)
      if (ios /= 0) exit
      if (rd%n_lines == size(rd%lines)) then
        allocate(tmp(2*size(rd%lines)))
        tmp(1:rd%n_lines) = rd%lines(1:rd%n_lines)
        call move_alloc(tmp, rd%lines)
      end if
      rd%n_lines = rd%n_lines + 1
      rd%lines(rd%n_lines)%s = line
    end do
    if (ios == iostat_end) ios = 0
  end subroutine load_lines

  !> One record of any length; a last line without a newline counts as a record.
  subroutine read_record(u, line, ios, iomsg)
    integer, intent(in) :: u
    character(len=:), allocatable, intent(out) :: line
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: iomsg
    character(len=256) :: buf
    integer :: nread
    logical :: started
    line = ''
    started = .false.
    do
      nread = 0
      read(u, '(a)', advance='no', iostat=ios, iomsg=iomsg, size=nread) buf
      if (ios == 0) then
        line = line//buf
        started = .true.
      else if (ios == iostat_eor) then
        line = line//buf(1:nread)
        ios = 0
        return
      else if (ios == iostat_end) then
        if (started .or. nread > 0) then
          line = line//buf(1:nread)
          ios = 0
        end if
        return
      else
        return
      end if
    end do
  end subroutine read_record

  !> True when some line holds more than blanks and comments.
  pure logical function has_content(rd)
    type(reader_t), intent(in) :: rd
    integer :: il, ic
    character(len=1) :: c
    has_content = .false.
    do il = 1, rd%n_lines
      do ic = 1, len(rd%lines(il)%s)
        c = rd%lines(il)%s(ic:ic)
        if (c == '!') exit
        if (.not. is_blank(c)) then
          has_content = .true.
          return
        end if
      end do
    end do
  end function has_content

  ! ------------------------------------------------------------------------ scanning

  !> Find the groups (`&name ... /`) and tokenise their text; report text outside groups,
  !! groups not closed, and groups starting on the line where another one ends.
  subroutine scan_source(rd)
    type(reader_t), intent(inout) :: rd
    integer :: il, ic, n, j, cur, last_tok, io
    character(len=1) :: c
    character(len=:), allocatable :: line
    logical :: stray_done, comma_pending
    cur = 0
    do il = 1, rd%n_lines
      line = rd%lines(il)%s
      n = len(line)
      ic = 1
      stray_done = .false.
      comma_pending = .false.
      last_tok = 0
      do while (ic <= n)
        c = line(ic:ic)
        if (cur == 0) then                               ! outside any group
          if (c == '!') exit
          if (is_blank(c)) then
            ic = ic + 1
            cycle
          end if
          if (c == '&') then
            j = name_end(line, ic + 1)
            if (j > ic) then
              if (lower(line(ic+1:j)) /= 'end') then
                call open_occ(rd, lower(line(ic+1:j)), il)
                cur = rd%n_occ
                ic = j + 1
                cycle
              end if
            end if
          end if
          if (.not. stray_done) then
            call add_err(rd, il, 'text outside any group: '''// &
              trim(adjustl(line(ic:)))//''' (the namelist reader would ignore it; '// &
              'a misplaced ''/''?); allowed: comments starting with !, and groups &<name> ... /')
            stray_done = .true.
          end if
          exit
        end if
        select case (c)                                  ! inside group cur
        case ('!')
          if (comma_pending .and. last_tok > 0) rd%occ(cur)%tok(last_tok)%comma_comment = .true.
          exit
        case (',')
          comma_pending = .true.
          ic = ic + 1
        case ('/')
          rd%occ(cur)%closed = .true.
          rd%occ(cur)%end_line = il
          cur = 0
          ic = ic + 1
        case ('=')
          call push_token(rd%occ(cur), '=', il, tk_equals)
          last_tok = rd%occ(cur)%n_tok
          comma_pending = .false.
          ic = ic + 1
        case ('&')
          j = name_end(line, ic + 1)
          if (lower(line(ic+1:j)) == 'end') then
            rd%occ(cur)%closed = .true.
            rd%occ(cur)%end_line = il
            cur = 0
            ic = j + 1
          else
            call add_err(rd, rd%occ(cur)%line, label(rd, cur)//': not closed with ''/'' '// &
              'before line '//itoa(il)//'; allowed: end every group with a line holding /')
            rd%occ(cur)%readable = .false.
            rd%occ(cur)%end_line = il - 1
            cur = 0                                      ! the '&' opens the next group
          end if
        case ('''', '"')
          j = string_end(line, ic)
          if (j == 0) then
            call add_err(rd, il, label(rd, cur)//': text value '//line(ic:)// &
              ' is not closed on this line; allowed: text in matching quotes on one line')
            rd%occ(cur)%readable = .false.
            j = n
          end if
          call push_token(rd%occ(cur), line(ic:j), il, tk_string)
          last_tok = rd%occ(cur)%n_tok
          comma_pending = .false.
          ic = j + 1
        case default
          if (is_blank(c)) then
            ic = ic + 1
            cycle
          end if
          j = word_end(line, ic)
          call push_token(rd%occ(cur), line(ic:j), il, tk_word)
          last_tok = rd%occ(cur)%n_tok
          comma_pending = .false.
          ic = j + 1
        end select
      end do
    end do
    if (cur /= 0) then
      call add_err(rd, rd%occ(cur)%line, label(rd, cur)//': not closed with ''/'' (end of '// &
        'file reached); allowed: end every group with a line holding /')
      rd%occ(cur)%readable = .false.
      rd%occ(cur)%end_line = rd%n_lines
    end if
    do io = 1, rd%n_occ
      call build_assignments(rd%occ(io))
    end do
  end subroutine scan_source

  !> Start a new group occurrence at line il.
  subroutine open_occ(rd, name, il)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: name
    integer, intent(in) :: il
    type(occ_t), allocatable :: tmp(:)
    integer :: k, io
    if (rd%n_occ == size(rd%occ)) then
      allocate(tmp(2*size(rd%occ)))
      tmp(1:rd%n_occ) = rd%occ(1:rd%n_occ)
      call move_alloc(tmp, rd%occ)
    end if
    k = 1
    do io = 1, rd%n_occ
      if (rd%occ(io)%group == name) k = k + 1
    end do
    rd%n_occ = rd%n_occ + 1
    rd%occ(rd%n_occ)%group = name
    rd%occ(rd%n_occ)%index = k
    rd%occ(rd%n_occ)%line = il
    rd%occ(rd%n_occ)%end_line = il
    allocate(rd%occ(rd%n_occ)%tok(16), rd%occ(rd%n_occ)%asg(8))
    if (rd%n_occ > 1) then
      if (rd%occ(rd%n_occ - 1)%closed .and. rd%occ(rd%n_occ - 1)%end_line == il) then
        call add_err(rd, il, label(rd, rd%n_occ)//': starts on the line where '// &
          label(rd, rd%n_occ - 1)//' ends (the reader would skip it); allowed: each group '// &
          'starting on a line of its own')
        rd%occ(rd%n_occ)%readable = .false.
      end if
    end if
  end subroutine open_occ

  !> Append a token to an occurrence.
  subroutine push_token(o, text, line, kind)
    type(occ_t), intent(inout) :: o
    character(len=*), intent(in) :: text
    integer, intent(in) :: line, kind
    type(token_t), allocatable :: tmp(:)
    if (o%n_tok == size(o%tok)) then
      allocate(tmp(2*size(o%tok)))
      tmp(1:o%n_tok) = o%tok(1:o%n_tok)
      call move_alloc(tmp, o%tok)
    end if
    o%n_tok = o%n_tok + 1
    o%tok(o%n_tok)%text = text
    o%tok(o%n_tok)%line = line
    o%tok(o%n_tok)%kind = kind
  end subroutine push_token

  !> Group the tokens of an occurrence into `name = values` (and stray text).
  subroutine build_assignments(o)
    type(occ_t), intent(inout) :: o
    integer :: it, ia, p, q, j
    character(len=:), allocatable :: w
    logical :: is_name
    ia = 0
    it = 1
    do while (it <= o%n_tok)
      is_name = .false.
      if (o%tok(it)%kind == tk_word .and. it < o%n_tok) is_name = o%tok(it+1)%kind == tk_equals
      if (is_name) then
        call new_asg(o, ia, it + 2, o%tok(it)%line, .false.)
        w = lower(o%tok(it)%text)
        p = index(w, '(')
        if (p > 0) then
          q = index(w, ')', back=.true.)
          if (q < p) q = len(w) + 1
          o%asg(ia)%base = trim(w(1:p-1))
          o%asg(ia)%sub = compact(w(p+1:q-1))
        else
          o%asg(ia)%base = w
          o%asg(ia)%sub = ''
        end if
        it = it + 2
        cycle
      end if
      if (ia == 0) then
        call new_asg(o, ia, it, o%tok(it)%line, .true.)
      else if (o%tok(it)%kind == tk_equals .and. .not. o%asg(ia)%stray) then
        call new_asg(o, ia, it, o%tok(it)%line, .true.)
      end if
      o%asg(ia)%t2 = it
      it = it + 1
    end do
    do ia = 1, o%n_asg
      o%asg(ia)%value = ''
      do j = o%asg(ia)%t1, o%asg(ia)%t2
        if (j > o%asg(ia)%t1) o%asg(ia)%value = o%asg(ia)%value//', '
        o%asg(ia)%value = o%asg(ia)%value//o%tok(j)%text
      end do
    end do
  end subroutine build_assignments

  !> Append an assignment whose values start at token t1.
  subroutine new_asg(o, ia, t1, line, stray)
    type(occ_t), intent(inout) :: o
    integer, intent(out) :: ia
    integer, intent(in) :: t1, line
    logical, intent(in) :: stray
    type(assign_t), allocatable :: tmp(:)
    if (o%n_asg == size(o%asg)) then
      allocate(tmp(2*size(o%asg)))
      tmp(1:o%n_asg) = o%asg(1:o%n_asg)
      call move_alloc(tmp, o%asg)
    end if
    o%n_asg = o%n_asg + 1
    ia = o%n_asg
    o%asg(ia)%t1 = t1
    o%asg(ia)%t2 = t1 - 1
    o%asg(ia)%line = line
    o%asg(ia)%stray = stray
    o%asg(ia)%base = ''
    o%asg(ia)%sub = ''
  end subroutine new_asg

  !> Unknown group names, repeated single groups, missing required groups.
  subroutine check_groups(rd, n_of, first_of)
    type(reader_t), intent(inout) :: rd
    integer, intent(out) :: n_of(n_groups)    !! occurrences of each known group
    integer, intent(out) :: first_of(n_groups) !! first occurrence (0 if none)
    integer :: io, ig
    character(len=:), allocatable :: lines_txt
    n_of = 0
    first_of = 0
    do io = 1, rd%n_occ
      ig = group_id(rd%occ(io)%group)
      if (ig == 0) then
        call add_err(rd, rd%occ(io)%line, '&'//rd%occ(io)%group//': unknown group'// &
          suggestion(rd%occ(io)%group, group_names)//'; allowed: '//join_list(group_names, '&'))
        rd%occ(io)%ok = .false.
        cycle
      end if
      n_of(ig) = n_of(ig) + 1
      if (first_of(ig) == 0) first_of(ig) = io
    end do
    do ig = 1, 3
      if (n_of(ig) > 1) then
        lines_txt = ''
        do io = 1, rd%n_occ
          if (rd%occ(io)%group /= trim(group_names(ig))) cycle
          if (len(lines_txt) > 0) lines_txt = lines_txt//', '
          lines_txt = lines_txt//itoa(rd%occ(io)%line)
          if (rd%occ(io)%index > 1) rd%occ(io)%ok = .false.
        end do
        do io = 1, rd%n_occ
          if (rd%occ(io)%group == trim(group_names(ig)) .and. rd%occ(io)%index == 2) &
            call add_err(rd, rd%occ(io)%line, '&'//trim(group_names(ig))//': group given '// &
              itoa(n_of(ig))//' times (lines '//lines_txt//'); allowed: once (merge them)')
        end do
      end if
    end do
    if (n_of(1) == 0) call add_err(rd, 0, '&run: group missing (required); add &run with at '// &
      'least t_end = <simulated time [s]>')
    if (n_of(3) == 0) call add_err(rd, 0, '&grid: group missing (required); add &grid with at '// &
      'least h = <cell size [m]>')
    if (n_of(4) == 0) call add_err(rd, 0, '&material: group missing (at least one required); '// &
      'add &material with name, E, nu, rho (and sigma_y for model = ''j2'')')
    if (n_of(5) == 0) call add_err(rd, 0, '&body: group missing (at least one required); add '// &
      '&body with r_inner and r_outer (a ring)')
  end subroutine check_groups

  ! ------------------------------------------------------------------ reading a group

  !> Rewind and skip to the first line of occurrence io; false if it cannot be read.
  subroutine goto_group(rd, io, u, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    logical, intent(out) :: ok
    integer :: il, ios
    character(len=512) :: iomsg
    ok = .false.
    rd%occ(io)%ok = .false.
    if (.not. rd%occ(io)%readable) return
    rewind(u, iostat=ios, iomsg=iomsg)
    do il = 1, rd%occ(io)%line - 1
      if (ios /= 0) exit
      read(u, '(a)', iostat=ios, iomsg=iomsg)
    end do
    if (ios /= 0) then
      call add_err(rd, rd%occ(io)%line, label(rd, io)//': cannot position the file on this '// &
        'group ('//trim(iomsg)//')')
      return
    end if
    ok = .true.
  end subroutine goto_group

  !> Size of the internal file that holds the lines of occurrence io (one blank more than the
  !! longest line: gfortran cannot read a group whose '/' ends the last record). Reading every
  !! group from its own lines means a group never reads into the next one, and a last line
  !! without a newline is read like any other. ok is false when the group cannot be read
  !! (a structural error was reported).
  subroutine group_shape(rd, io, width, n_rec, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    integer, intent(out) :: width, n_rec
    logical, intent(out) :: ok
    integer :: il
    ok = .false.
    rd%occ(io)%ok = .false.
    width = 1
    n_rec = 1
    if (.not. rd%occ(io)%readable) return
    n_rec = max(rd%occ(io)%end_line, rd%occ(io)%line) - rd%occ(io)%line + 1
    do il = rd%occ(io)%line, rd%occ(io)%line + n_rec - 1
      width = max(width, len(rd%lines(il)%s) + 1)
    end do
    ok = .true.
  end subroutine group_shape

  !> The lines of occurrence io, one per record.
  subroutine fill_buffer(rd, io, buf)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    character(len=*), intent(out) :: buf(:)
    integer :: k
    do k = 1, size(buf)
      buf(k) = rd%lines(rd%occ(io)%line + k - 1)%s
    end do
  end subroutine fill_buffer

  !> After a failed namelist read: diagnose every `name = value` of the occurrence;
  !! explained is false when that finds nothing.
  subroutine read_failed(rd, io, explained)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    logical, intent(out) :: explained
    integer :: n0
    rd%occ(io)%ok = .false.
    n0 = rd%n_err
    call diagnose(rd, io)
    explained = rd%n_err > n0
  end subroutine read_failed

  !> A read failure the diagnosis could not explain: the same group was read again from the
  !! file itself (unit u); report the runtime's message at or near the line where that read
  !! stopped (STYLE B 1: backspace, read the line, count the lines after it).
  subroutine where_failed(rd, io, u, ios_file, iomsg)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    integer, intent(in) :: ios_file        !! status of the read from the file
    character(len=*), intent(in) :: iomsg  !! the runtime's message (first read)
    integer :: ios, remaining, ln
    character(len=:), allocatable :: text
    character(len=512) :: msg2
    ln = 0
    if (ios_file /= 0) then
      backspace(u, iostat=ios, iomsg=msg2)
      if (ios == 0) call read_record(u, text, ios, msg2)
      if (ios == 0) then
        remaining = 0
        do
          read(u, '(a)', iostat=ios, iomsg=msg2)
          if (ios /= 0) exit
          remaining = remaining + 1
        end do
        ln = rd%n_lines - remaining
      end if
    end if
    if (ln < rd%occ(io)%line .or. ln > rd%occ(io)%end_line) ln = rd%occ(io)%line
    call add_err(rd, ln, label(rd, io)//': cannot read this group, at or near this line ('''// &
      trim(adjustl(rd%lines(ln)%s))//'''): '//trim(iomsg)//'; allowed: name = value pairs '// &
      'of '//var_list(rd%occ(io)%group))
    rd%occ(io)%ok = .false.
  end subroutine where_failed

  !> Check names, subscripts, value types and value counts of every assignment in a group.
  subroutine diagnose(rd, io)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(var_info_t), allocatable :: vars(:)
    integer :: ia, vi
    character(len=:), allocatable :: written
    call get_group_vars(rd%occ(io)%group, vars)
    do ia = 1, rd%occ(io)%n_asg
      if (rd%occ(io)%asg(ia)%stray) then
        call add_err(rd, rd%occ(io)%asg(ia)%line, label(rd, io)//': unexpected text '''// &
          rd%occ(io)%asg(ia)%value//''' (expected <name> = <value>)'// &
          missing_equals(rd%occ(io)%tok(rd%occ(io)%asg(ia)%t1)%text, vars)//'; allowed: '// &
          var_list(rd%occ(io)%group))
        cycle
      end if
      vi = find_var(vars, rd%occ(io)%asg(ia)%base)
      if (vi == 0) then
        written = rd%occ(io)%tok(rd%occ(io)%asg(ia)%t1 - 2)%text
        call add_err(rd, rd%occ(io)%asg(ia)%line, label(rd, io)//': '//written//' = '// &
          rd%occ(io)%asg(ia)%value//': unknown variable'// &
          suggestion(rd%occ(io)%asg(ia)%base, var_names(vars))//'; allowed: '// &
          var_list(rd%occ(io)%group))
        cycle
      end if
      call check_values(rd, io, ia, vars(vi), vars)
    end do
  end subroutine diagnose

  !> Subscript, types and count of the values of assignment ia (variable vi).
  subroutine check_values(rd, io, ia, vi, vars)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, ia
    type(var_info_t), intent(in) :: vi, vars(:)
    integer :: cap, i1, i2, p, ios, it, r, count, ln
    character(len=:), allocatable :: name, sub, t, rest, head, what
    real(wp) :: x
    integer :: n
    logical :: l
    character(len=256) :: msg
    name = trim(vi%name)
    sub = rd%occ(io)%asg(ia)%sub
    ln = rd%occ(io)%asg(ia)%line
    cap = vi%n
    head = label(rd, io)//': '//name
    if (len(sub) > 0) head = head//'('//sub//')'
    head = head//' = '//rd%occ(io)%asg(ia)%value//': '
    if (len(sub) > 0) then
      p = index(sub, ':')
      i1 = -1
      i2 = -1
      if (p == 0) then
        read(sub, *, iostat=ios, iomsg=msg) i1
        i2 = i1
      else
        read(sub(1:p-1), *, iostat=ios, iomsg=msg) i1
        if (ios == 0) read(sub(p+1:), *, iostat=ios, iomsg=msg) i2
      end if
      if (ios /= 0 .or. i1 < 1 .or. i2 < i1 .or. i2 > cap) then
        if (cap == 1) then
          call add_err(rd, ln, head//'subscript on a single value; allowed: '//name// &
            ' = <value>, '//allowed_text(rd%occ(io)%group, name))
        else
          call add_err(rd, ln, head//'subscript out of range; allowed: '//name//'(1) to '// &
            name//'('//itoa(cap)//'), '//allowed_text(rd%occ(io)%group, name))
        end if
        return
      end if
      cap = i2 - i1 + 1
    end if
    count = 0
    do it = rd%occ(io)%asg(ia)%t1, rd%occ(io)%asg(ia)%t2
      t = rd%occ(io)%tok(it)%text
      if (it < rd%occ(io)%asg(ia)%t2 .and. rd%occ(io)%tok(it)%comma_comment) then
        call add_err(rd, rd%occ(io)%tok(it)%line, head//'a comment follows the comma after '''// &
          t//''' while the values go on on the next line (gfortran cannot read that); '// &
          'allowed: no comment there, or no comma before it')
        return
      end if
      if (rd%occ(io)%tok(it)%kind == tk_string) then
        if (vi%kind == 'c') then
          count = count + 1
          cycle
        end if
        call add_err(rd, rd%occ(io)%tok(it)%line, head//t//' is text in quotes, not '// &
          kind_text(vi%kind)//'; allowed: '//allowed_text(rd%occ(io)%group, name))
        return
      end if
      if (vi%kind == 'c') then
        call add_err(rd, rd%occ(io)%tok(it)%line, head//'text values need quotes ('// &
          name//' = '''//t//''')'//missing_equals(t, vars)//'; allowed: '// &
          allowed_text(rd%occ(io)%group, name))
        return
      end if
      r = 1
      rest = t
      p = index(t, '*')
      if (p > 1) then
        if (verify(t(1:p-1), '0123456789') == 0) then
          read(t(1:p-1), *, iostat=ios, iomsg=msg) r
          if (ios /= 0) r = 1
          rest = t(p+1:)
        end if
      end if
      if (len(rest) > 0) then
        select case (vi%kind)
        case ('r')
          read(rest, *, iostat=ios, iomsg=msg) x
        case ('i')
          read(rest, *, iostat=ios, iomsg=msg) n
        case default
          read(rest, *, iostat=ios, iomsg=msg) l
        end select
        if (ios /= 0) then
          what = ''''//rest//''' is not '//kind_text(vi%kind)
          if (vi%kind == 'i') what = ''''//rest//''' is not an integer (or is too large)'
          call add_err(rd, rd%occ(io)%tok(it)%line, head//what//missing_equals(rest, vars)// &
            '; allowed: '//allowed_text(rd%occ(io)%group, name))
          return
        end if
      end if
      count = count + r
    end do
    if (count > cap) then
      call add_err(rd, ln, head//'too many values ('//itoa(count)//' given, '//itoa(cap)// &
        ' allowed); allowed: '//allowed_text(rd%occ(io)%group, name))
    end if
  end subroutine check_values

  !> ' (is a ''='' missing after x?)' when word t is a variable name of the group.
  pure function missing_equals(t, vars) result(s)
    character(len=*), intent(in) :: t
    type(var_info_t), intent(in) :: vars(:)
    character(len=:), allocatable :: s
    s = ''
    if (find_var(vars, lower(t)) > 0) s = ' (is a ''='' missing after '''//t//'''?)'
  end function missing_equals

  pure function kind_text(kind) result(s)
    character(len=1), intent(in) :: kind
    character(len=:), allocatable :: s
    select case (kind)
    case ('r')
      s = 'a real number'
    case ('i')
      s = 'an integer'
    case ('l')
      s = 'a logical (.true. or .false.)'
    case default
      s = 'text in quotes'
    end select
  end function kind_text

  ! ------------------------------------------------------------------------ validators

  !> True when x is finite and not NaN (NaN tested first: no FP trap).
  elemental logical function finite(x)
    real(wp), intent(in) :: x
    finite = .false.
    if (ieee_is_nan(x)) return
    finite = ieee_is_finite(x)
  end function finite

  !> Check a real: finite, given (when required), in range. True when usable and given.
  logical function chk_real(rd, io, var, x, required, gt, ge, lt, le) result(good)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: x
    logical, intent(in) :: required
    real(wp), intent(in), optional :: gt, ge, lt, le
    logical :: bad
    good = .false.
    if (.not. finite(x)) then
      call err_var(rd, io, var, fmt_real(x), 'not a finite number')
      return
    end if
    if (x == unset_real) then
      if (required) call err_missing(rd, io, var)
      return
    end if
    bad = .false.
    if (present(gt)) bad = bad .or. .not. (x > gt)
    if (present(ge)) bad = bad .or. .not. (x >= ge)
    if (present(lt)) bad = bad .or. .not. (x < lt)
    if (present(le)) bad = bad .or. .not. (x <= le)
    if (bad) then
      call err_var(rd, io, var, fmt_real(x), 'out of range')
      return
    end if
    good = .true.
  end function chk_real

  !> Check an integer: given (when required), >= ge. True when usable and given.
  logical function chk_int(rd, io, var, n, required, ge) result(good)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    integer, intent(in) :: n
    logical, intent(in) :: required
    integer, intent(in) :: ge
    good = .false.
    if (n == iunset) then
      if (required) call err_missing(rd, io, var)
      return
    end if
    if (n < ge) then
      call err_var(rd, io, var, itoa(n), 'out of range')
      return
    end if
    good = .true.
  end function chk_int

  !> Check a 2-vector: finite, both components or none. Returns 2 (given), 0 (not given,
  !! reported when required) or -1 (error reported).
  integer function chk_vec(rd, io, var, v, required) result(n_given)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: v(2)
    logical, intent(in) :: required
    n_given = -1
    if (.not. all(finite(v))) then
      call err_var(rd, io, var, fmt_vec(v), 'not finite numbers')
      return
    end if
    n_given = count(v /= unset_real)
    if (n_given == 1) then
      call err_var(rd, io, var, fmt_vec(v), 'needs 2 values, only one was given')
      n_given = -1
    else if (n_given == 0 .and. required) then
      call err_missing(rd, io, var)
    end if
  end function chk_vec

  !> Check an enumeration value (case-insensitive); returns its code or 0 (error reported).
  integer function chk_enum(rd, io, var, text, names) result(id)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    character(len=*), intent(in) :: text
    character(len=*), intent(in) :: names(:)
    integer :: k
    character(len=:), allocatable :: t
    t = lower(trim(adjustl(text)))
    id = 0
    do k = 1, size(names)
      if (t == trim(names(k))) id = k
    end do
    if (id == 0) call err_var(rd, io, var, quote(trim(adjustl(text))), 'not an allowed value'// &
      suggestion(t, names))
  end function chk_enum

  !> Check the length of a text value.
  logical function chk_text(rd, io, var, text, max_len) result(good)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    character(len=*), intent(in) :: text
    integer, intent(in) :: max_len
    good = len_trim(adjustl(text)) <= max_len
    if (.not. good) call err_var(rd, io, var, quote(trim(adjustl(text))), 'too long ('// &
      itoa(len_trim(adjustl(text)))//' characters)')
  end function chk_text

  ! ------------------------------------------------------------------------ the groups

  !> &run
  subroutine read_run(rd, io, u, r)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    type(run_cfg_t), intent(inout) :: r
    character(len=long_len) :: title, output_dir
    real(wp) :: t_end, cfl, dt, history_every, snapshot_every, checkpoint_every, depth
    real(wp) :: gravity(2)
    integer :: threads
    namelist /run/ title, output_dir, t_end, cfl, dt, history_every, snapshot_every, &
                   checkpoint_every, depth, gravity, threads
    integer :: ios, n0
    character(len=512) :: iomsg, iomsg2
    integer :: width, n_rec
    logical :: ok
    title = ''
    output_dir = ''
    t_end = unset_real
    cfl = 0.2_wp
    dt = 0.0_wp
    history_every = 0.0_wp
    snapshot_every = 0.0_wp
    checkpoint_every = 0.0_wp
    depth = 1.0_wp
    gravity = 0.0_wp
    threads = 0
    call group_shape(rd, io, width, n_rec, ok)
    if (.not. ok) return
    block
      character(len=width) :: buf(n_rec)
      call fill_buffer(rd, io, buf)
      read(buf, nml=run, iostat=ios, iomsg=iomsg)
    end block
    if (ios /= 0) then
      call read_failed(rd, io, ok)
      if (.not. ok) then                  ! not explained: where does the runtime stop?
        call goto_group(rd, io, u, ok)
        if (ok) read(u, nml=run, iostat=ios, iomsg=iomsg2)
        call where_failed(rd, io, u, ios, iomsg)
      end if
      return
    end if
    rd%occ(io)%read_ok = .true.
    n0 = rd%n_err
    if (chk_text(rd, io, 'title', title, name_len)) r%title = trim(adjustl(title))
    if (chk_text(rd, io, 'output_dir', output_dir, path_len)) &
      r%output_dir = trim(adjustl(output_dir))
    if (chk_real(rd, io, 't_end', t_end, .true., gt=0.0_wp)) r%t_end = t_end
    if (chk_real(rd, io, 'cfl', cfl, .false., gt=0.0_wp, le=2.0_wp)) then
      r%cfl = cfl
      if (cfl > 1.0_wp) call warn_var(rd, io, 'cfl', 'above 1 the explicit step exceeds the '// &
        'stable limit of the grid: the run will most likely stop with exit 4 (use 0.1-0.3)')
    end if
    if (chk_real(rd, io, 'dt', dt, .false., ge=0.0_wp)) r%dt = dt
    if (chk_real(rd, io, 'history_every', history_every, .false., ge=0.0_wp)) &
      r%history_every = history_every
    if (chk_real(rd, io, 'snapshot_every', snapshot_every, .false., ge=0.0_wp)) &
      r%snapshot_every = snapshot_every
    if (chk_real(rd, io, 'checkpoint_every', checkpoint_every, .false., ge=0.0_wp)) &
      r%checkpoint_every = checkpoint_every
    if (chk_real(rd, io, 'depth', depth, .false., gt=0.0_wp)) r%depth = depth
    if (chk_vec(rd, io, 'gravity', gravity, .false.) == 2) r%gravity = gravity
    if (chk_int(rd, io, 'threads', threads, .false., 0)) r%threads = threads
    rd%occ(io)%ok = rd%n_err == n0
  end subroutine read_run

  !> &solver
  subroutine read_solver(rd, io, u, s)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    type(solver_cfg_t), intent(inout) :: s
    character(len=long_len) :: basis, scheme, plane
    real(wp) :: flip, mass_scale, damping
    logical :: deterministic
    namelist /solver/ basis, scheme, flip, plane, mass_scale, damping, deterministic
    integer :: ios, n0, id
    character(len=512) :: iomsg, iomsg2
    integer :: width, n_rec
    logical :: ok
    basis = 'cpdi2'
    scheme = 'musl'
    plane = 'strain'
    flip = 1.0_wp
    mass_scale = 1.0_wp
    damping = 0.0_wp
    deterministic = .false.
    call group_shape(rd, io, width, n_rec, ok)
    if (.not. ok) return
    block
      character(len=width) :: buf(n_rec)
      call fill_buffer(rd, io, buf)
      read(buf, nml=solver, iostat=ios, iomsg=iomsg)
    end block
    if (ios /= 0) then
      call read_failed(rd, io, ok)
      if (.not. ok) then                  ! not explained: where does the runtime stop?
        call goto_group(rd, io, u, ok)
        if (ok) read(u, nml=solver, iostat=ios, iomsg=iomsg2)
        call where_failed(rd, io, u, ios, iomsg)
      end if
      return
    end if
    rd%occ(io)%read_ok = .true.
    n0 = rd%n_err
    id = chk_enum(rd, io, 'basis', basis, basis_names)
    if (id > 0) then
      s%basis = basis_names(id)
      s%basis_id = id
    end if
    id = chk_enum(rd, io, 'scheme', scheme, scheme_names)
    if (id > 0) then
      s%scheme = scheme_names(id)
      s%scheme_id = id
    end if
    id = chk_enum(rd, io, 'plane', plane, plane_names)
    if (id > 0) then
      s%plane = plane_names(id)
      s%plane_id = id
    end if
    if (chk_real(rd, io, 'flip', flip, .false., ge=0.0_wp, le=1.0_wp)) s%flip = flip
    if (chk_real(rd, io, 'mass_scale', mass_scale, .false., ge=1.0_wp)) s%mass_scale = mass_scale
    if (chk_real(rd, io, 'damping', damping, .false., ge=0.0_wp)) s%damping = damping
    s%deterministic = deterministic
    rd%occ(io)%ok = rd%n_err == n0
  end subroutine read_solver

  !> &grid
  subroutine read_grid(rd, io, u, g)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    type(grid_cfg_t), intent(inout) :: g
    real(wp) :: h, lower(2), upper(2)
    namelist /grid/ h, lower, upper
    integer :: ios, n0, nl, nu
    character(len=512) :: iomsg, iomsg2
    integer :: width, n_rec
    logical :: ok
    h = unset_real
    lower = unset_real
    upper = unset_real
    call group_shape(rd, io, width, n_rec, ok)
    if (.not. ok) return
    block
      character(len=width) :: buf(n_rec)
      call fill_buffer(rd, io, buf)
      read(buf, nml=grid, iostat=ios, iomsg=iomsg)
    end block
    if (ios /= 0) then
      call read_failed(rd, io, ok)
      if (.not. ok) then                  ! not explained: where does the runtime stop?
        call goto_group(rd, io, u, ok)
        if (ok) read(u, nml=grid, iostat=ios, iomsg=iomsg2)
        call where_failed(rd, io, u, ios, iomsg)
      end if
      return
    end if
    rd%occ(io)%read_ok = .true.
    n0 = rd%n_err
    if (chk_real(rd, io, 'h', h, .true., gt=0.0_wp)) g%h = h
    nl = chk_vec(rd, io, 'lower', lower, .false.)
    nu = chk_vec(rd, io, 'upper', upper, .false.)
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
    rd%occ(io)%ok = rd%n_err == n0
  end subroutine read_grid

  !> &material
  subroutine read_material(rd, io, u, m)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    type(material_cfg_t), intent(inout) :: m
    character(len=long_len) :: name, model, rate_law
    real(wp) :: E, nu, rho, sigma_y, hardening, cs_d, cs_q
    namelist /material/ name, model, E, nu, rho, sigma_y, hardening, rate_law, cs_d, cs_q
    integer :: ios, n0, id
    character(len=512) :: iomsg, iomsg2
    integer :: width, n_rec
    logical :: ok
    name = ''
    model = 'j2'
    E = unset_real
    nu = unset_real
    rho = unset_real
    sigma_y = unset_real
    hardening = 0.0_wp
    rate_law = 'none'
    cs_d = 40.4_wp
    cs_q = 5.0_wp
    call group_shape(rd, io, width, n_rec, ok)
    if (.not. ok) return
    block
      character(len=width) :: buf(n_rec)
      call fill_buffer(rd, io, buf)
      read(buf, nml=material, iostat=ios, iomsg=iomsg)
    end block
    if (ios /= 0) then
      call read_failed(rd, io, ok)
      if (.not. ok) then                  ! not explained: where does the runtime stop?
        call goto_group(rd, io, u, ok)
        if (ok) read(u, nml=material, iostat=ios, iomsg=iomsg2)
        call where_failed(rd, io, u, ios, iomsg)
      end if
      return
    end if
    rd%occ(io)%read_ok = .true.
    n0 = rd%n_err
    if (len_trim(name) == 0) then
      call err_missing(rd, io, 'name')
    else if (chk_text(rd, io, 'name', name, name_len)) then
      m%name = trim(adjustl(name))
    end if
    id = chk_enum(rd, io, 'model', model, model_names)
    if (id > 0) then
      m%model = model_names(id)
      m%model_id = id
    end if
    if (chk_real(rd, io, 'E', E, .true., gt=0.0_wp)) m%E = E
    if (chk_real(rd, io, 'nu', nu, .true., ge=0.0_wp, lt=0.5_wp)) m%nu = nu
    if (chk_real(rd, io, 'rho', rho, .true., gt=0.0_wp)) m%rho = rho
    if (chk_real(rd, io, 'sigma_y', sigma_y, id == MODEL_J2, gt=0.0_wp)) then
      m%sigma_y = sigma_y
      if (id /= MODEL_J2 .and. id > 0) call warn_var(rd, io, 'sigma_y', &
        'used only by model = ''j2'' (model is '''//trim(m%model)//''')')
    end if
    if (chk_real(rd, io, 'hardening', hardening, .false., ge=0.0_wp)) m%hardening = hardening
    id = chk_enum(rd, io, 'rate_law', rate_law, rate_law_names)
    if (id > 0) then
      m%rate_law = rate_law_names(id)
      m%rate_law_id = id
      if (id == RATE_COWPER_SYMONDS .and. m%model_id /= MODEL_J2) call warn_var(rd, io, &
        'rate_law', 'used only by model = ''j2'' (it scales the yield stress)')
    end if
    if (chk_real(rd, io, 'cs_d', cs_d, .false., gt=0.0_wp)) m%cs_d = cs_d
    if (chk_real(rd, io, 'cs_q', cs_q, .false., gt=0.0_wp)) m%cs_q = cs_q
    rd%occ(io)%ok = rd%n_err == n0
  end subroutine read_material

  !> &body
  subroutine read_body(rd, io, u, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    type(body_cfg_t), intent(inout) :: b
    character(len=long_len) :: shape, material, sector
    real(wp) :: center(2), r_inner, r_outer, size(2), velocity(2)
    integer :: n_thick, n_circ, n_x, n_y
    namelist /body/ shape, material, center, r_inner, r_outer, n_thick, n_circ, sector, size, &
                    n_x, n_y, velocity
    integer :: ios, n0, id, sid, parts, ns
    character(len=512) :: iomsg, iomsg2
    integer :: width, n_rec
    logical :: ok, okr
    shape = 'ring'
    material = ''
    center = 0.0_wp
    r_inner = unset_real
    r_outer = unset_real
    n_thick = iunset
    n_circ = iunset
    sector = ''
    size = unset_real
    n_x = iunset
    n_y = iunset
    velocity = 0.0_wp
    call group_shape(rd, io, width, n_rec, ok)
    if (.not. ok) return
    block
      character(len=width) :: buf(n_rec)
      call fill_buffer(rd, io, buf)
      read(buf, nml=body, iostat=ios, iomsg=iomsg)
    end block
    if (ios /= 0) then
      call read_failed(rd, io, ok)
      if (.not. ok) then                  ! not explained: where does the runtime stop?
        call goto_group(rd, io, u, ok)
        if (ok) read(u, nml=body, iostat=ios, iomsg=iomsg2)
        call where_failed(rd, io, u, ios, iomsg)
      end if
      return
    end if
    rd%occ(io)%read_ok = .true.
    n0 = rd%n_err
    id = chk_enum(rd, io, 'shape', shape, shape_names)
    if (id > 0) then
      b%shape = shape_names(id)
      b%shape_id = id
    end if
    if (chk_text(rd, io, 'material', material, name_len)) b%material = trim(adjustl(material))
    if (chk_vec(rd, io, 'center', center, .false.) == 2) b%center = center
    if (chk_vec(rd, io, 'velocity', velocity, .false.) == 2) b%velocity = velocity
    b%sector = sector_names(SECTOR_FULL)
    b%sector_id = SECTOR_FULL
    if (id == SHAPE_RING) then
      okr = chk_real(rd, io, 'r_inner', r_inner, .true., gt=0.0_wp)
      if (okr) b%r_inner = r_inner
      if (chk_real(rd, io, 'r_outer', r_outer, .true., gt=0.0_wp)) then
        b%r_outer = r_outer
        if (okr .and. .not. (r_inner < r_outer)) call err_var(rd, io, 'r_inner', &
          fmt_real(r_inner), 'not below r_outer = '//fmt_real(r_outer))
      end if
      if (n_thick == iunset) n_thick = 16
      if (chk_int(rd, io, 'n_thick', n_thick, .false., 1)) b%n_thick = n_thick
      sid = SECTOR_FULL
      if (len_trim(sector) > 0) sid = chk_enum(rd, io, 'sector', sector, sector_names)
      if (sid > 0) then
        b%sector = sector_names(sid)
        b%sector_id = sid
      end if
      if (n_circ == iunset) n_circ = 0
      parts = 1
      if (sid == SECTOR_HALF) parts = 2
      if (sid == SECTOR_QUARTER) parts = 4
      if (n_circ /= 0 .and. n_circ < 3) then
        call err_var(rd, io, 'n_circ', itoa(n_circ), 'out of range')
      else if (mod(n_circ, parts) /= 0) then
        call err_var(rd, io, 'n_circ', itoa(n_circ), 'not divisible by '//itoa(parts)// &
          ' (sector = '''//trim(b%sector)//''')')
      else
        b%n_circ = n_circ
      end if
      ns = count(size /= unset_real)
      if (ns > 0 .or. n_x /= iunset .or. n_y /= iunset) call warn_group(rd, io, &
        'size, n_x, n_y are ignored for shape = ''ring''')
    else if (id == SHAPE_RECT) then
      if (chk_vec(rd, io, 'size', size, .true.) == 2) then
        if (all(size > 0.0_wp)) then
          b%size = size
        else
          call err_var(rd, io, 'size', fmt_vec(size), 'out of range')
        end if
      end if
      if (chk_int(rd, io, 'n_x', n_x, .true., 1)) b%n_x = n_x
      if (chk_int(rd, io, 'n_y', n_y, .true., 1)) b%n_y = n_y
      if (r_inner /= unset_real .or. r_outer /= unset_real .or. n_thick /= iunset .or. &
          n_circ /= iunset .or. len_trim(sector) > 0) call warn_group(rd, io, &
        'r_inner, r_outer, n_thick, n_circ, sector are ignored for shape = ''rect''')
    end if
    rd%occ(io)%ok = rd%n_err == n0
  end subroutine read_body

  !> &wall
  subroutine read_wall(rd, io, u, w)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    type(wall_cfg_t), intent(inout) :: w
    character(len=long_len) :: contact
    real(wp) :: point(2), normal(2), friction, velocity(2), ramp
    real(wp) :: motion_t(max_table), motion_f(max_table)
    namelist /wall/ point, normal, contact, friction, velocity, ramp, motion_t, motion_f
    integer :: ios, n0, id, nt, nf, k
    character(len=512) :: iomsg, iomsg2
    integer :: width, n_rec
    logical :: ok, table_ok
    real(wp) :: length
    point = unset_real
    normal = unset_real
    contact = 'frictionless'
    friction = 0.0_wp
    velocity = 0.0_wp
    ramp = 0.0_wp
    motion_t = unset_real
    motion_f = unset_real
    call group_shape(rd, io, width, n_rec, ok)
    if (.not. ok) return
    block
      character(len=width) :: buf(n_rec)
      call fill_buffer(rd, io, buf)
      read(buf, nml=wall, iostat=ios, iomsg=iomsg)
    end block
    if (ios /= 0) then
      call read_failed(rd, io, ok)
      if (.not. ok) then                  ! not explained: where does the runtime stop?
        call goto_group(rd, io, u, ok)
        if (ok) read(u, nml=wall, iostat=ios, iomsg=iomsg2)
        call where_failed(rd, io, u, ios, iomsg)
      end if
      return
    end if
    rd%occ(io)%read_ok = .true.
    n0 = rd%n_err
    if (chk_vec(rd, io, 'point', point, .true.) == 2) w%point = point
    if (chk_vec(rd, io, 'normal', normal, .true.) == 2) then
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
    id = chk_enum(rd, io, 'contact', contact, contact_names)
    if (id > 0) then
      w%contact = contact_names(id)
      w%contact_id = id
    end if
    if (chk_real(rd, io, 'friction', friction, .false., ge=0.0_wp)) then
      if (friction > 0.0_wp .and. id > 0 .and. id /= CONTACT_COULOMB) then
        call err_var(rd, io, 'friction', fmt_real(friction), 'has no effect with contact = '''// &
          trim(w%contact)//'''; set contact = ''coulomb'' or friction = 0')
      else
        w%friction = friction
      end if
    end if
    if (chk_vec(rd, io, 'velocity', velocity, .false.) == 2) w%velocity = velocity
    if (chk_real(rd, io, 'ramp', ramp, .false., ge=0.0_wp)) w%ramp = ramp
    ! motion table: the entries given are the leading non-sentinel ones
    table_ok = .true.
    call table_count(rd, io, 'motion_t', motion_t, nt, table_ok)
    call table_count(rd, io, 'motion_f', motion_f, nf, table_ok)
    if (table_ok .and. nt /= nf) then
      call err_var(rd, io, 'motion_f', fmt_list(motion_f(1:nf)), itoa(nf)// &
        ' values but motion_t has '//itoa(nt))
      table_ok = .false.
    end if
    if (table_ok .and. nt > 0) then
      if (motion_t(1) < 0.0_wp) then
        call err_var(rd, io, 'motion_t', fmt_list(motion_t(1:nt)), 'motion_t(1) = '// &
          fmt_real(motion_t(1))//' is negative')
        table_ok = .false.
      end if
    end if
    if (table_ok) then
      do k = 2, nt
        if (.not. (motion_t(k) > motion_t(k-1))) then
          call err_var(rd, io, 'motion_t', fmt_list(motion_t(1:nt)), 'not strictly '// &
            'increasing: motion_t('//itoa(k)//') = '//fmt_real(motion_t(k))// &
            ' <= motion_t('//itoa(k-1)//') = '//fmt_real(motion_t(k-1)))
          table_ok = .false.
          exit
        end if
      end do
    end if
    if (table_ok) then
      w%n_motion = nt
      w%motion_t(1:nt) = motion_t(1:nt)
      w%motion_f(1:nt) = motion_f(1:nt)
      if (nt > 0 .and. w%ramp > 0.0_wp) call warn_var(rd, io, 'ramp', &
        'ignored: the motion table replaces it')
    end if
    rd%occ(io)%ok = rd%n_err == n0
  end subroutine read_wall

  !> Number of table entries given (leading, without gaps); reports gaps and non-finite values.
  subroutine table_count(rd, io, var, t, n, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: t(:)
    integer, intent(out) :: n
    logical, intent(inout) :: ok
    integer :: k, last
    n = 0
    last = 0
    do k = 1, size(t)
      if (.not. finite(t(k))) then
        call err_var(rd, io, var, fmt_real(t(k)), var//'('//itoa(k)//') is not a finite number')
        ok = .false.
        return
      end if
      if (t(k) /= unset_real) last = k
    end do
    do k = 1, last
      if (t(k) == unset_real) then
        call err_var(rd, io, var, fmt_list(t(1:last)), var//'('//itoa(k)// &
          ') not given (a gap in the table)')
        ok = .false.
        return
      end if
    end do
    n = last
  end subroutine table_count

  !> &probe
  subroutine read_probe(rd, io, u, p)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io, u
    type(probe_cfg_t), intent(inout) :: p
    real(wp) :: point(2)
    namelist /probe/ point
    integer :: ios, n0
    character(len=512) :: iomsg, iomsg2
    integer :: width, n_rec
    logical :: ok
    point = unset_real
    call group_shape(rd, io, width, n_rec, ok)
    if (.not. ok) return
    block
      character(len=width) :: buf(n_rec)
      call fill_buffer(rd, io, buf)
      read(buf, nml=probe, iostat=ios, iomsg=iomsg)
    end block
    if (ios /= 0) then
      call read_failed(rd, io, ok)
      if (.not. ok) then                  ! not explained: where does the runtime stop?
        call goto_group(rd, io, u, ok)
        if (ok) read(u, nml=probe, iostat=ios, iomsg=iomsg2)
        call where_failed(rd, io, u, ios, iomsg)
      end if
      return
    end if
    rd%occ(io)%read_ok = .true.
    n0 = rd%n_err
    if (chk_vec(rd, io, 'point', point, .true.) == 2) p%point = point
    rd%occ(io)%ok = rd%n_err == n0
  end subroutine read_probe

  ! ---------------------------------------------------------------- checks across groups

  !> Defaults that depend on other groups, references, bounds, the fixed time step.
  subroutine cross_checks(rd, cfg, first_of, occ_mat, occ_body)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(inout) :: cfg
    integer, intent(in) :: first_of(n_groups), occ_mat(:), occ_body(:)
    integer :: k, j, id, io_run, io_solver, io_grid, kc
    logical :: all_named, all_ok
    character(len=:), allocatable :: names_txt, want
    real(wp) :: lo(2), hi(2), cd, c, vmax, dt_lim, ms, thick
    type(material_cfg_t) :: m

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

    ! given grid bounds contain every body
    if (io_grid > 0) then
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
    end if

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
    if (all_ok) then
      if (cfg%run%dt > 0.0_wp) then
        ms = cfg%solver%mass_scale
        cd = 0.0_wp
        kc = 1
        do k = 1, size(cfg%materials)
          m = cfg%materials(k)
          c = sqrt(m%E*(1.0_wp - m%nu)/((1.0_wp + m%nu)*(1.0_wp - 2.0_wp*m%nu)) / (m%rho*ms))
          if (c > cd) then
            cd = c
            kc = k
          end if
        end do
        vmax = 0.0_wp
        do k = 1, size(cfg%bodies)
          vmax = max(vmax, sqrt(sum(cfg%bodies(k)%velocity**2)))
        end do
        dt_lim = cfg%grid%h/(cd + vmax)
        if (cfg%run%dt > dt_lim) call err_var(rd, io_run, 'dt', fmt_real(cfg%run%dt), &
          'above the stable limit h / (c_d + v_max) = '//fmt_short(dt_lim)//' s at cfl = 1 '// &
          '(h = '//fmt_short(cfg%grid%h)//' m; c_d = sqrt((lambda + 2 mu)/rho) = '// &
          fmt_short(cd)//' m/s of &material #'//itoa(kc)//'; v_max = '//fmt_short(vmax)// &
          ' m/s)', '0 < dt <= '//fmt_short(dt_lim)//' [s], or dt = 0 (time step from cfl)')
      end if
    end if

    ! advice: thin walls need cells smaller than the wall thickness
    if (io_grid > 0) then
      if (rd%occ(io_grid)%ok) then
        do k = 1, size(cfg%bodies)
          if (.not. rd%occ(occ_body(k))%ok .or. cfg%bodies(k)%shape_id /= SHAPE_RING) cycle
          thick = cfg%bodies(k)%r_outer - cfg%bodies(k)%r_inner
          if (cfg%grid%h >= thick) call warn_var(rd, io_grid, 'h', 'not smaller than the '// &
            'wall thickness '//fmt_short(thick)//' m of &body #'//itoa(k)//': both faces '// &
            'of the wall share grid nodes and the wall bends wrongly (use h < thickness)')
        end do
      end if
    end if
  end subroutine cross_checks

  !> Bounding box of the material of a body (ring sector convention of mpm_particles:
  !! half = the side x >= centre, quarter = x >= centre and y >= centre).
  pure subroutine body_box(b, lo, hi)
    type(body_cfg_t), intent(in) :: b
    real(wp), intent(out) :: lo(2), hi(2)
    if (b%shape_id == SHAPE_RECT) then
      lo = b%center - 0.5_wp*b%size
      hi = b%center + 0.5_wp*b%size
      return
    end if
    lo = b%center - b%r_outer
    hi = b%center + b%r_outer
    if (b%sector_id == SECTOR_HALF .or. b%sector_id == SECTOR_QUARTER) lo(1) = b%center(1)
    if (b%sector_id == SECTOR_QUARTER) lo(2) = b%center(2)
  end subroutine body_box

  ! ------------------------------------------------------------------------ messages

  !> Record an error at a line (0: none) of the file.
  subroutine add_err(rd, line, text)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: line
    character(len=*), intent(in) :: text
    call push_msg(rd%err, rd%n_err, line, file_line(rd, line)//text)
  end subroutine add_err

  !> Record a warning at a line (0: none) of the file.
  subroutine add_warn(rd, line, text)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: line
    character(len=*), intent(in) :: text
    call push_msg(rd%warn, rd%n_warn, line, file_line(rd, line)//text)
  end subroutine add_warn

  pure function file_line(rd, line) result(s)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: line
    character(len=:), allocatable :: s
    if (line > 0) then
      s = rd%file//':'//itoa(line)//': '
    else
      s = rd%file//': '
    end if
  end function file_line

  subroutine push_msg(list, n, line, text)
    type(msg_t), allocatable, intent(inout) :: list(:)
    integer, intent(inout) :: n
    integer, intent(in) :: line
    character(len=*), intent(in) :: text
    type(msg_t), allocatable :: tmp(:)
    if (n == size(list)) then
      allocate(tmp(2*size(list)))
      tmp(1:n) = list(1:n)
      call move_alloc(tmp, list)
    end if
    n = n + 1
    list(n)%line = line
    list(n)%text = text
  end subroutine push_msg

  !> `file:line: &group #k: var = value: what; allowed: ...` for occurrence io; the line and
  !! the value are those of the variable's assignment when the file has one.
  subroutine err_var(rd, io, var, value, what, allowed)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var, value, what
    character(len=*), intent(in), optional :: allowed
    integer :: ln
    character(len=:), allocatable :: v, al
    call var_where(rd, io, var, value, ln, v)
    if (present(allowed)) then
      al = allowed
    else
      al = allowed_text(rd%occ(io)%group, var)
    end if
    call add_err(rd, ln, label(rd, io)//': '//var//' = '//v//': '//what//'; allowed: '//al)
    rd%occ(io)%ok = .false.
  end subroutine err_var

  !> A required variable is missing in occurrence io.
  subroutine err_missing(rd, io, var)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    call add_err(rd, rd%occ(io)%line, label(rd, io)//': '//var//': missing (required); '// &
      'allowed: '//allowed_text(rd%occ(io)%group, var))
    rd%occ(io)%ok = .false.
  end subroutine err_missing

  !> A warning about a variable of occurrence io.
  subroutine warn_var(rd, io, var, what)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var, what
    integer :: ln
    character(len=:), allocatable :: v
    call var_where(rd, io, var, '', ln, v)
    if (len(v) > 0) then
      call add_warn(rd, ln, label(rd, io)//': '//var//' = '//v//': '//what)
    else
      call add_warn(rd, ln, label(rd, io)//': '//var//': '//what)
    end if
  end subroutine warn_var

  !> A warning about occurrence io as a whole.
  subroutine warn_group(rd, io, what)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: what
    call add_warn(rd, rd%occ(io)%line, label(rd, io)//': '//what)
  end subroutine warn_group

  !> Line and value text of variable var in occurrence io (the last assignment to it).
  subroutine var_where(rd, io, var, value, ln, v)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var, value
    integer, intent(out) :: ln
    character(len=:), allocatable, intent(out) :: v
    integer :: ia, k
    ln = rd%occ(io)%line
    v = value
    ia = 0
    do k = rd%occ(io)%n_asg, 1, -1
      if (rd%occ(io)%asg(k)%stray) cycle
      if (rd%occ(io)%asg(k)%base == lower(var)) then
        ia = k
        exit
      end if
    end do
    if (ia == 0) return
    ln = rd%occ(io)%asg(ia)%line
    if (len(rd%occ(io)%asg(ia)%sub) == 0 .and. len(rd%occ(io)%asg(ia)%value) > 0) &
      v = rd%occ(io)%asg(ia)%value
  end subroutine var_where

  !> Messages sorted by line (stable; messages without a line last), one per line.
  function join_msgs(list, n) result(s)
    type(msg_t), intent(in) :: list(:)
    integer, intent(in) :: n
    character(len=:), allocatable :: s
    integer :: idx(n), key(n), i, j, t
    do i = 1, n
      idx(i) = i
      key(i) = list(i)%line
      if (key(i) <= 0) key(i) = huge(1)
    end do
    do i = 2, n
      t = idx(i)
      j = i - 1
      do while (j >= 1)
        if (key(idx(j)) <= key(t)) exit
        idx(j+1) = idx(j)
        j = j - 1
      end do
      idx(j+1) = t
    end do
    s = ''
    do i = 1, n
      call append_msg(s, list(idx(i))%text)
    end do
  end function join_msgs

  !> '&group' or '&group #k' for repeatable groups.
  pure function label(rd, io) result(s)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: io
    character(len=:), allocatable :: s
    integer :: ig
    s = '&'//rd%occ(io)%group
    ig = group_id(rd%occ(io)%group)
    if (ig > 0) then
      if (group_repeatable(ig)) s = s//' #'//itoa(rd%occ(io)%index)
    end if
  end function label

  pure integer function group_id(name)
    character(len=*), intent(in) :: name
    integer :: k
    group_id = 0
    do k = 1, n_groups
      if (name == trim(group_names(k))) group_id = k
    end do
  end function group_id

  !> The variables of a group (the namelist statements of the readers list the same).
  pure subroutine get_group_vars(group, v)
    character(len=*), intent(in) :: group
    type(var_info_t), allocatable, intent(out) :: v(:)
    select case (group)
    case ('run')
      v = [var_info_t('title', 'c', 1), var_info_t('output_dir', 'c', 1), &
           var_info_t('t_end', 'r', 1), var_info_t('cfl', 'r', 1), var_info_t('dt', 'r', 1), &
           var_info_t('history_every', 'r', 1), var_info_t('snapshot_every', 'r', 1), &
           var_info_t('checkpoint_every', 'r', 1), var_info_t('depth', 'r', 1), &
           var_info_t('gravity', 'r', 2), var_info_t('threads', 'i', 1)]
    case ('solver')
      v = [var_info_t('basis', 'c', 1), var_info_t('scheme', 'c', 1), &
           var_info_t('flip', 'r', 1), var_info_t('plane', 'c', 1), &
           var_info_t('mass_scale', 'r', 1), var_info_t('damping', 'r', 1), &
           var_info_t('deterministic', 'l', 1)]
    case ('grid')
      v = [var_info_t('h', 'r', 1), var_info_t('lower', 'r', 2), var_info_t('upper', 'r', 2)]
    case ('material')
      v = [var_info_t('name', 'c', 1), var_info_t('model', 'c', 1), var_info_t('E', 'r', 1), &
           var_info_t('nu', 'r', 1), var_info_t('rho', 'r', 1), var_info_t('sigma_y', 'r', 1), &
           var_info_t('hardening', 'r', 1), var_info_t('rate_law', 'c', 1), &
           var_info_t('cs_d', 'r', 1), var_info_t('cs_q', 'r', 1)]
    case ('body')
      v = [var_info_t('shape', 'c', 1), var_info_t('material', 'c', 1), &
           var_info_t('center', 'r', 2), var_info_t('r_inner', 'r', 1), &
           var_info_t('r_outer', 'r', 1), var_info_t('n_thick', 'i', 1), &
           var_info_t('n_circ', 'i', 1), var_info_t('sector', 'c', 1), &
           var_info_t('size', 'r', 2), var_info_t('n_x', 'i', 1), var_info_t('n_y', 'i', 1), &
           var_info_t('velocity', 'r', 2)]
    case ('wall')
      v = [var_info_t('point', 'r', 2), var_info_t('normal', 'r', 2), &
           var_info_t('contact', 'c', 1), var_info_t('friction', 'r', 1), &
           var_info_t('velocity', 'r', 2), var_info_t('ramp', 'r', 1), &
           var_info_t('motion_t', 'r', max_table), var_info_t('motion_f', 'r', max_table)]
    case ('probe')
      v = [var_info_t('point', 'r', 2)]
    case default
      allocate(v(0))
    end select
  end subroutine get_group_vars

  pure integer function find_var(vars, base)
    type(var_info_t), intent(in) :: vars(:)
    character(len=*), intent(in) :: base
    integer :: k
    find_var = 0
    do k = 1, size(vars)
      if (lower(trim(vars(k)%name)) == base) find_var = k
    end do
  end function find_var

  pure function var_list(group) result(s)
    character(len=*), intent(in) :: group
    character(len=:), allocatable :: s
    type(var_info_t), allocatable :: v(:)
    call get_group_vars(group, v)
    s = join_list(var_names(v), '')
  end function var_list

  !> The names of a list of variables (a contiguous array).
  pure function var_names(v) result(names)
    type(var_info_t), intent(in) :: v(:)
    character(len=16) :: names(size(v))
    integer :: k
    do k = 1, size(v)
      names(k) = v(k)%name
    end do
  end function var_names

  !> What a variable accepts, for messages (units in brackets, default in parentheses).
  function allowed_text(group, var) result(s)
    character(len=*), intent(in) :: group, var
    character(len=:), allocatable :: s
    select case (group//'.'//var)
    case ('run.title')
      s = 'text of at most 64 characters (default: the file name stem)'
    case ('run.output_dir')
      s = 'a folder path of at most 512 characters (default: out/<title>)'
    case ('run.t_end')
      s = 'a real number > 0 [s] (required)'
    case ('run.cfl')
      s = 'a real number with 0 < cfl <= 2 (default 0.2; above 1 is unstable, allowed for '// &
          'stability studies)'
    case ('run.dt')
      s = 'a real number >= 0 [s] (0 = from cfl; default 0)'
    case ('run.history_every', 'run.snapshot_every', 'run.checkpoint_every')
      s = 'a real number >= 0 [s] (default 0)'
    case ('run.depth')
      s = 'a real number > 0 [m] (default 1.0)'
    case ('run.gravity')
      s = '2 finite real numbers [m/s^2] (default 0, 0)'
    case ('run.threads')
      s = 'an integer >= 0 (0 = the OpenMP runtime default)'
    case ('solver.basis')
      s = enum_text(basis_names, 'cpdi2')
    case ('solver.scheme')
      s = enum_text(scheme_names, 'musl')
    case ('solver.plane')
      s = enum_text(plane_names, 'strain')
    case ('solver.flip')
      s = 'a real number with 0 <= flip <= 1 (default 1.0)'
    case ('solver.mass_scale')
      s = 'a real number >= 1 (default 1.0)'
    case ('solver.damping')
      s = 'a real number >= 0 [1/s] (default 0)'
    case ('solver.deterministic')
      s = '.true. or .false. (default .false.)'
    case ('grid.h')
      s = 'a real number > 0 [m] (required)'
    case ('grid.lower', 'grid.upper')
      s = '2 real numbers [m] each for lower and upper, lower < upper in both components, '// &
          'both given or neither (then fitted)'
    case ('material.name')
      s = 'text of 1 to 64 characters, unique among the &material groups (required)'
    case ('material.model')
      s = enum_text(model_names, 'j2')
    case ('material.E')
      s = 'a real number > 0 [Pa] (required)'
    case ('material.nu')
      s = 'a real number with 0 <= nu < 0.5 (required)'
    case ('material.rho')
      s = 'a real number > 0 [kg/m^3] (required)'
    case ('material.sigma_y')
      s = 'a real number > 0 [Pa] (required for model = ''j2'')'
    case ('material.hardening')
      s = 'a real number >= 0 [Pa] (default 0)'
    case ('material.rate_law')
      s = enum_text(rate_law_names, 'none')
    case ('material.cs_d')
      s = 'a real number > 0 [1/s] (default 40.4)'
    case ('material.cs_q')
      s = 'a real number > 0 (default 5)'
    case ('body.shape')
      s = enum_text(shape_names, 'ring')
    case ('body.material')
      s = 'the name of a &material (default: the first material)'
    case ('body.center')
      s = '2 finite real numbers [m] (default 0, 0)'
    case ('body.r_inner')
      s = 'a real number with 0 < r_inner < r_outer [m] (required for shape = ''ring'')'
    case ('body.r_outer')
      s = 'a real number > r_inner [m] (required for shape = ''ring'')'
    case ('body.n_thick')
      s = 'an integer >= 1 (default 16)'
    case ('body.n_circ')
      s = '0 (particles about square) or an integer >= 3, divisible by 2 for sector = '// &
          '''half'' and by 4 for ''quarter'' (default 0)'
    case ('body.sector')
      s = enum_text(sector_names, 'full')
    case ('body.size')
      s = '2 real numbers > 0 [m] (required for shape = ''rect'')'
    case ('body.n_x', 'body.n_y')
      s = 'an integer >= 1 (required for shape = ''rect'')'
    case ('body.velocity', 'wall.velocity')
      s = '2 finite real numbers [m/s] (default 0, 0)'
    case ('wall.point', 'probe.point')
      s = '2 finite real numbers [m] (required)'
    case ('wall.normal')
      s = '2 real numbers forming a unit vector, |normal| = 1 within 1e-6 (required)'
    case ('wall.contact')
      s = enum_text(contact_names, 'frictionless')
    case ('wall.friction')
      s = 'a real number >= 0, and > 0 only with contact = ''coulomb'' (default 0)'
    case ('wall.ramp')
      s = 'a real number >= 0 [s] (default 0)'
    case ('wall.motion_t')
      s = 'up to 64 times [s], >= 0 and strictly increasing, as many as motion_f (default none)'
    case ('wall.motion_f')
      s = 'up to 64 finite factors, as many as motion_t (default none)'
    case default
      s = 'see docs/input.md'
    end select
  end function allowed_text

  pure function enum_text(names, default) result(s)
    character(len=*), intent(in) :: names(:), default
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(names)
      if (k > 1) s = s//', '
      s = s//quote(trim(names(k)))
    end do
    s = s//' (default '//quote(default)//')'
  end function enum_text

  pure function join_list(names, prefix) result(s)
    character(len=*), intent(in) :: names(:), prefix
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(names)
      if (k > 1) s = s//', '
      s = s//prefix//trim(names(k))
    end do
  end function join_list

  !> ' (did you mean ''x''?)' for the closest name, or ''.
  pure function suggestion(word, names) result(s)
    character(len=*), intent(in) :: word, names(:)
    character(len=:), allocatable :: s
    integer :: k, d, best, kbest, lw, ln
    s = ''
    best = huge(1)
    kbest = 0
    do k = 1, size(names)
      d = edit_distance(lower(word), lower(trim(names(k))))
      if (d < best) then
        best = d
        kbest = k
      end if
    end do
    if (kbest == 0) return
    lw = len(word)
    ln = len_trim(names(kbest))
    if ((best <= 2 .and. best < min(lw, ln)) .or. &
        (min(lw, ln) >= 3 .and. index(lower(trim(names(kbest))), lower(word)) == 1) .or. &
        (min(lw, ln) >= 3 .and. index(lower(word), lower(trim(names(kbest)))) == 1)) &
      s = ' (did you mean '''//trim(names(kbest))//'''?)'
  end function suggestion

  !> Levenshtein distance.
  pure integer function edit_distance(a, b) result(d)
    character(len=*), intent(in) :: a, b
    integer :: row(0:len(b)), prev(0:len(b)), i, j
    do j = 0, len(b)
      prev(j) = j
    end do
    do i = 1, len(a)
      row(0) = i
      do j = 1, len(b)
        row(j) = min(prev(j) + 1, row(j-1) + 1, prev(j-1) + merge(0, 1, a(i:i) == b(j:j)))
      end do
      prev = row
    end do
    d = prev(len(b))
  end function edit_distance

  ! ------------------------------------------------------------------------ text utilities

  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: k, c
    t = s
    do k = 1, len(s)
      c = iachar(s(k:k))
      if (c >= iachar('A') .and. c <= iachar('Z')) t(k:k) = achar(c + 32)
    end do
  end function lower

  pure logical function is_blank(c)
    character(len=1), intent(in) :: c
    is_blank = c == ' ' .or. c == achar(9) .or. c == achar(13) .or. c == achar(10)
  end function is_blank

  pure logical function is_name_char(c)
    character(len=1), intent(in) :: c
    is_name_char = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z') .or. &
                   (c >= '0' .and. c <= '9') .or. c == '_'
  end function is_name_char

  !> Last index of the name starting at i (i - 1 when there is none).
  pure integer function name_end(s, i) result(j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: i
    j = i - 1
    do while (j + 1 <= len(s))
      if (.not. is_name_char(s(j+1:j+1))) exit
      j = j + 1
    end do
  end function name_end

  !> Last index of the word starting at i; `name(...)` counts as one word.
  pure integer function word_end(s, i) result(j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: i
    integer :: p
    character(len=1) :: c
    j = i
    do while (j + 1 <= len(s))
      c = s(j+1:j+1)
      if (is_blank(c) .or. index(',=/!''"', c) > 0) exit
      if (c == '(') then
        p = index(s(j+1:), ')')
        if (p == 0) then
          j = len(s)
          exit
        end if
        j = j + p
        cycle
      end if
      j = j + 1
    end do
  end function word_end

  !> Index of the quote closing the text that opens at i ('' and "" inside), 0 if none.
  pure integer function string_end(s, i) result(j)
    character(len=*), intent(in) :: s
    integer, intent(in) :: i
    character(len=1) :: q
    q = s(i:i)
    j = i + 1
    do while (j <= len(s))
      if (s(j:j) == q) then
        if (j + 1 <= len(s)) then
          if (s(j+1:j+1) == q) then
            j = j + 2
            cycle
          end if
        end if
        return
      end if
      j = j + 1
    end do
    j = 0
  end function string_end

  !> s without blanks.
  pure function compact(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: k
    t = ''
    do k = 1, len(s)
      if (.not. is_blank(s(k:k))) t = t//s(k:k)
    end do
  end function compact

  pure function itoa(n) result(s)
    integer, intent(in) :: n
    character(len=:), allocatable :: s
    character(len=24) :: buf
    character(len=128) :: msg
    integer :: ios
    write(buf, '(i0)', iostat=ios, iomsg=msg) n
    s = trim(buf)
  end function itoa

  !> Text in single quotes, inner quotes doubled (namelist syntax).
  pure function quote(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: k
    t = ''''
    do k = 1, len(s)
      if (s(k:k) == '''') then
        t = t//''''''
      else
        t = t//s(k:k)
      end if
    end do
    t = t//''''
  end function quote

  !> Name of the file without folder and extension.
  pure function file_stem(path) result(stem)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: stem
    integer :: i, j
    i = index(path, '/', back=.true.)
    stem = trim(path(i+1:))
    j = index(stem, '.', back=.true.)
    if (j > 1) stem = stem(1:j-1)
    if (len(stem) == 0) stem = 'case'
    if (len(stem) > name_len) stem = stem(1:name_len)
  end function file_stem

  !> Shortest decimal text that reads back to exactly x (NaN, Infinity for non-finite).
  function fmt_real(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=48) :: buf
    character(len=16) :: fmt
    character(len=:), allocatable :: b, digits
    integer :: d, ios, p, e
    real(wp) :: y
    logical :: neg
    character(len=128) :: msg
    if (ieee_is_nan(x)) then
      s = 'NaN'
      return
    end if
    if (.not. ieee_is_finite(x)) then
      s = 'Infinity'
      if (x < 0.0_wp) s = '-Infinity'
      return
    end if
    if (x == 0.0_wp) then
      s = '0.0'
      return
    end if
    do d = 0, 17
      if (abs(x) > 1.0e307_wp .and. d < 16) cycle        ! rounding up could overflow on reading
      write(fmt, '(a,i0,a)', iostat=ios, iomsg=msg) '(es40.', d, 'e4)'
      write(buf, fmt, iostat=ios, iomsg=msg) x
      read(buf, *, iostat=ios, iomsg=msg) y
      if (ios == 0 .and. y == x) exit
    end do
    b = trim(adjustl(buf))
    neg = b(1:1) == '-'
    if (neg) b = b(2:)
    p = index(b, 'E')
    read(b(p+1:), *, iostat=ios, iomsg=msg) e
    digits = b(1:1)//b(3:p-1)                         ! d.ddd -> dddd
    do while (len(digits) > 1)
      if (digits(len(digits):len(digits)) /= '0') exit
      digits = digits(1:len(digits)-1)
    end do
    if (e >= 0 .and. e <= 4) then                      ! plain decimal
      if (len(digits) <= e + 1) then
        s = digits//fill('0', e + 1 - len(digits))//'.0'
      else
        s = digits(1:e+1)//'.'//digits(e+2:)
      end if
    else if (e < 0 .and. e >= -3) then
      s = '0.'//fill('0', -e - 1)//digits
    else
      if (len(digits) > 1) then
        s = digits(1:1)//'.'//digits(2:)//'e'//itoa(e)
      else
        s = digits//'.0e'//itoa(e)
      end if
    end if
    if (neg) s = '-'//s
  end function fmt_real

  !> n copies of character c.
  pure function fill(c, n) result(s)
    character(len=1), intent(in) :: c
    integer, intent(in) :: n
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, n
      s = s//c
    end do
  end function fill

  !> Six significant digits, for derived numbers in messages.
  function fmt_short(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    real(wp) :: y
    integer :: ios
    character(len=128) :: msg
    if (.not. finite(x)) then
      s = fmt_real(x)
      return
    end if
    write(buf, '(es13.5e3)', iostat=ios, iomsg=msg) x
    read(buf, *, iostat=ios, iomsg=msg) y
    s = trim(adjustl(buf))
    if (ios == 0) s = fmt_real(y)
  end function fmt_short

  !> Two numbers; a component not given shows as (none).
  function fmt_vec(v) result(s)
    real(wp), intent(in) :: v(2)
    character(len=:), allocatable :: s
    s = fmt_given(v(1))//', '//fmt_given(v(2))
  end function fmt_vec

  function fmt_given(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    s = fmt_real(x)
    if (finite(x)) then
      if (x == unset_real) s = '(none)'
    end if
  end function fmt_given

  function fmt_list(v) result(s)
    real(wp), intent(in) :: v(:)
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(v)
      if (k > 1) s = s//', '
      s = s//fmt_given(v(k))
    end do
  end function fmt_list

  ! ======================================================================== writing

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
    integer :: k
    w%unit = unit
    call w_line(w, '! tubempm input as resolved: every variable with its value (defaults '// &
      'filled in). SI units.')
    call w_line(w, '! Lines starting with ! are comments; see docs/input.md for every variable.')
    call write_run(w, cfg%run)
    call write_solver(w, cfg%solver)
    call write_grid(w, cfg%grid)
    if (allocated(cfg%materials)) then
      do k = 1, size(cfg%materials)
        call write_material(w, cfg%materials(k), k)
      end do
    end if
    if (allocated(cfg%bodies)) then
      do k = 1, size(cfg%bodies)
        call write_body(w, cfg%bodies(k), k)
      end do
    end if
    if (allocated(cfg%walls)) then
      do k = 1, size(cfg%walls)
        if (.not. cfg%walls(k)%mirror) call write_wall(w, cfg%walls(k), k)
      end do
    end if
    if (allocated(cfg%probes)) then
      do k = 1, size(cfg%probes)
        call write_probe(w, cfg%probes(k), k)
      end do
    end if
    stat = 0
    errmsg = ''
    if (w%ios /= 0) then
      stat = EXIT_IO
      errmsg = 'cannot write the input echo ('//trim(w%iomsg)//')'
    end if
  end subroutine write_config_unit

  subroutine write_run(w, r)
    type(writer_t), intent(inout) :: w
    type(run_cfg_t), intent(in) :: r
    call w_line(w, '')
    call w_line(w, '&run')
    if (len_trim(r%title) > 0) then
      call w_kv(w, 'title', quote(trim(r%title)), 'label of the case')
    else
      call w_unset(w, 'title', 'default: the file name stem')
    end if
    if (len_trim(r%output_dir) > 0) then
      call w_kv(w, 'output_dir', quote(trim(r%output_dir)), 'folder for all outputs')
    else
      call w_unset(w, 'output_dir', 'default: out/<title>')
    end if
    if (unset_neg(r%t_end)) then
      call w_unset(w, 't_end', 'required: simulated time [s]')
    else
      call w_kv(w, 't_end', fmt_real(r%t_end), 'simulated time [s]')
    end if
    call w_kv(w, 'cfl', fmt_real(r%cfl), 'dt = cfl h / (c_d + max speed) [-]')
    call w_kv(w, 'dt', fmt_real(r%dt), 'fixed time step if > 0 [s]')
    call w_kv(w, 'history_every', fmt_real(r%history_every), 'history.csv interval [s]')
    call w_kv(w, 'snapshot_every', fmt_real(r%snapshot_every), 'snapshot interval [s]')
    call w_kv(w, 'checkpoint_every', fmt_real(r%checkpoint_every), &
      'wall-clock checkpoint interval [s]')
    call w_kv(w, 'depth', fmt_real(r%depth), 'out-of-plane length [m]')
    call w_kv(w, 'gravity', fmt_vec(r%gravity), 'body acceleration [m/s^2]')
    call w_kv(w, 'threads', itoa(r%threads), 'OpenMP threads (0 = runtime default)')
    call w_line(w, '/')
  end subroutine write_run

  subroutine write_solver(w, s)
    type(writer_t), intent(inout) :: w
    type(solver_cfg_t), intent(in) :: s
    call w_line(w, '')
    call w_line(w, '&solver')
    call w_kv(w, 'basis', quote(trim(s%basis)), join_list(basis_names, '')//' [-]')
    call w_kv(w, 'scheme', quote(trim(s%scheme)), join_list(scheme_names, '')//' [-]')
    call w_kv(w, 'flip', fmt_real(s%flip), 'FLIP fraction (1 FLIP, 0 PIC) [-]')
    call w_kv(w, 'plane', quote(trim(s%plane)), join_list(plane_names, '')//' [-]')
    call w_kv(w, 'mass_scale', fmt_real(s%mass_scale), 'density multiplier [-]')
    call w_kv(w, 'damping', fmt_real(s%damping), 'mass-proportional damping [1/s]')
    call w_kv(w, 'deterministic', fmt_logical(s%deterministic), &
      'results independent of the thread count')
    call w_line(w, '/')
  end subroutine write_solver

  subroutine write_grid(w, g)
    type(writer_t), intent(inout) :: w
    type(grid_cfg_t), intent(in) :: g
    call w_line(w, '')
    call w_line(w, '&grid')
    if (unset_neg(g%h)) then
      call w_unset(w, 'h', 'required: cell size [m]')
    else
      call w_kv(w, 'h', fmt_real(g%h), 'cell size [m]')
    end if
    if (g%fitted) then
      call w_line(w, '  ! lower, upper: not given, the domain is fitted around the bodies '// &
        'and walls')
    else
      call w_kv(w, 'lower', fmt_vec(g%lower), 'lower domain corner [m]')
      call w_kv(w, 'upper', fmt_vec(g%upper), 'upper domain corner [m]')
    end if
    call w_line(w, '/')
  end subroutine write_grid

  subroutine write_material(w, m, k)
    type(writer_t), intent(inout) :: w
    type(material_cfg_t), intent(in) :: m
    integer, intent(in) :: k
    call w_line(w, '')
    call w_line(w, '&material                             ! #'//itoa(k))
    if (len_trim(m%name) > 0) then
      call w_kv(w, 'name', quote(trim(m%name)), 'label used by &body')
    else
      call w_unset(w, 'name', 'required: label used by &body')
    end if
    call w_kv(w, 'model', quote(trim(m%model)), join_list(model_names, ''))
    call w_real_req(w, 'E', m%E, 'Young''s modulus [Pa]')
    call w_real_req(w, 'nu', m%nu, 'Poisson''s ratio [-]')
    call w_real_req(w, 'rho', m%rho, 'density [kg/m^3]')
    if (unset_neg(m%sigma_y)) then
      call w_unset(w, 'sigma_y', 'required for model = ''j2'': initial yield stress [Pa]')
    else
      call w_kv(w, 'sigma_y', fmt_real(m%sigma_y), 'initial yield stress [Pa]')
    end if
    call w_kv(w, 'hardening', fmt_real(m%hardening), 'linear isotropic hardening modulus [Pa]')
    call w_kv(w, 'rate_law', quote(trim(m%rate_law)), join_list(rate_law_names, ''))
    call w_kv(w, 'cs_d', fmt_real(m%cs_d), 'Cowper-Symonds D [1/s]')
    call w_kv(w, 'cs_q', fmt_real(m%cs_q), 'Cowper-Symonds q [-]')
    call w_line(w, '/')
  end subroutine write_material

  subroutine write_body(w, b, k)
    type(writer_t), intent(inout) :: w
    type(body_cfg_t), intent(in) :: b
    integer, intent(in) :: k
    logical :: rect
    rect = b%shape_id == SHAPE_RECT
    call w_line(w, '')
    call w_line(w, '&body                                 ! #'//itoa(k))
    call w_kv(w, 'shape', quote(trim(b%shape)), join_list(shape_names, ''))
    if (len_trim(b%material) > 0) then
      call w_kv(w, 'material', quote(trim(b%material)), 'a &material name')
    else
      call w_unset(w, 'material', 'default: the first material')
    end if
    call w_kv(w, 'center', fmt_vec(b%center), 'centre [m]')
    if (rect) then
      call w_line(w, '  ! r_inner, r_outer, n_thick, n_circ, sector: for rings only')
      if (unset_neg(b%size(1)) .or. unset_neg(b%size(2))) then
        call w_unset(w, 'size', 'required: rectangle sides [m]')
      else
        call w_kv(w, 'size', fmt_vec(b%size), 'rectangle sides [m]')
      end if
      if (b%n_x == 0) then
        call w_unset(w, 'n_x', 'required: particles along x')
      else
        call w_kv(w, 'n_x', itoa(b%n_x), 'particles along x')
      end if
      if (b%n_y == 0) then
        call w_unset(w, 'n_y', 'required: particles along y')
      else
        call w_kv(w, 'n_y', itoa(b%n_y), 'particles along y')
      end if
    else
      call w_real_req(w, 'r_inner', b%r_inner, 'inner radius [m]')
      call w_real_req(w, 'r_outer', b%r_outer, 'outer radius [m]')
      call w_kv(w, 'n_thick', itoa(b%n_thick), 'particles through the wall')
      call w_kv(w, 'n_circ', itoa(b%n_circ), 'particles around the whole ring (0 = auto)')
      call w_kv(w, 'sector', quote(trim(b%sector)), join_list(sector_names, ''))
      call w_line(w, '  ! size, n_x, n_y: for rectangles only')
    end if
    call w_kv(w, 'velocity', fmt_vec(b%velocity), 'initial velocity [m/s]')
    call w_line(w, '/')
  end subroutine write_body

  subroutine write_wall(w, wl, k)
    type(writer_t), intent(inout) :: w
    type(wall_cfg_t), intent(in) :: wl
    integer, intent(in) :: k
    call w_line(w, '')
    call w_line(w, '&wall                                 ! #'//itoa(k))
    if (unset_huge(wl%point)) then
      call w_unset(w, 'point', 'required: a point on the plane at t = 0 [m]')
    else
      call w_kv(w, 'point', fmt_vec(wl%point), 'a point on the plane at t = 0 [m]')
    end if
    if (unset_huge(wl%normal)) then
      call w_unset(w, 'normal', 'required: unit normal into the material side [-]')
    else
      call w_kv(w, 'normal', fmt_vec(wl%normal), 'unit normal into the material side [-]')
    end if
    call w_kv(w, 'contact', quote(trim(wl%contact)), join_list(contact_names, ''))
    call w_kv(w, 'friction', fmt_real(wl%friction), 'Coulomb coefficient [-]')
    call w_kv(w, 'velocity', fmt_vec(wl%velocity), 'prescribed velocity [m/s]')
    call w_kv(w, 'ramp', fmt_real(wl%ramp), 'smooth rise time of the velocity [s]')
    if (wl%n_motion > 0) then
      call w_line(w, '  ! motion table: times [s] and factors on velocity [-]')
      call w_table(w, 'motion_t', wl%motion_t(1:wl%n_motion))
      call w_table(w, 'motion_f', wl%motion_f(1:wl%n_motion))
    else
      call w_line(w, '  ! motion_t, motion_f: no motion table')
    end if
    call w_line(w, '/')
  end subroutine write_wall

  subroutine write_probe(w, p, k)
    type(writer_t), intent(inout) :: w
    type(probe_cfg_t), intent(in) :: p
    integer, intent(in) :: k
    call w_line(w, '')
    call w_line(w, '&probe                                ! #'//itoa(k))
    if (unset_huge(p%point)) then
      call w_unset(w, 'point', 'required: the particle nearest to it is recorded [m]')
    else
      call w_kv(w, 'point', fmt_vec(p%point), 'the particle nearest to it is recorded [m]')
    end if
    call w_line(w, '/')
  end subroutine write_probe

  !> A required real: its value, or a comment when it still holds the type default -1.
  subroutine w_real_req(w, name, x, comment)
    type(writer_t), intent(inout) :: w
    character(len=*), intent(in) :: name, comment
    real(wp), intent(in) :: x
    if (unset_neg(x)) then
      call w_unset(w, name, 'required: '//comment)
    else
      call w_kv(w, name, fmt_real(x), comment)
    end if
  end subroutine w_real_req

  !> A table, four values per line (no comments on its lines: see the gfortran note above).
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

  pure function fmt_logical(l) result(s)
    logical, intent(in) :: l
    character(len=:), allocatable :: s
    if (l) then
      s = '.true.'
    else
      s = '.false.'
    end if
  end function fmt_logical

  !> A required positive number still at its type default (-1).
  elemental logical function unset_neg(x)
    real(wp), intent(in) :: x
    unset_neg = .false.
    if (finite(x)) unset_neg = x == -1.0_wp
  end function unset_neg

  !> A required vector still at the sentinel unset_real.
  pure logical function unset_huge(v)
    real(wp), intent(in) :: v(2)
    unset_huge = .false.
    if (all(finite(v))) unset_huge = any(v == unset_real)
  end function unset_huge

  !> A case with one group of each kind and every default; the required numbers are left
  !! unset (written as comments by write_config). For `tubempm --defaults`.
  subroutine default_config(cfg)
    type(config_t), intent(out) :: cfg   !! the template case
    cfg%file = ''
    cfg%solver%basis_id = BASIS_CPDI2
    cfg%solver%scheme_id = SCHEME_MUSL
    cfg%solver%plane_id = PLANE_STRAIN
    allocate(cfg%materials(1), cfg%bodies(1), cfg%walls(1), cfg%probes(1))
    cfg%materials(1)%model_id = MODEL_J2
    cfg%materials(1)%rate_law_id = RATE_NONE
    cfg%bodies(1)%shape_id = SHAPE_RING
    cfg%bodies(1)%sector_id = SECTOR_FULL
    cfg%bodies(1)%material_id = 1
    cfg%walls(1)%point = unset_real
    cfg%walls(1)%normal = unset_real
    cfg%walls(1)%contact_id = CONTACT_FRICTIONLESS
    cfg%probes(1)%point = unset_real
  end subroutine default_config
end module mpm_config
