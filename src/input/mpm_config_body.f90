!> The rules of a &body (mpm_config_check's check_group calls them): the sector, a ring's radii
!! and n_circ, a tube's vertices and corners, a honeycomb's cells, a walls_file, and whether the
!! section can be meshed; and the count of a table's entries, which the other groups' tables
!! share. Every violation is reported at its variable, with what is allowed.
! SPDX-License-Identifier: MIT
module mpm_config_body
  use mpm_kinds, only: wp
  use mpm_constants, only: SHAPE_DISC, SHAPE_RING, SECTOR_FULL, SECTOR_HALF, SECTOR_QUARTER, &
                           SHAPE_TUBE, SHAPE_HONEYCOMB, SHAPE_WALLS, sector_names, pi
  use mpm_config_types, only: body_cfg_t, unset_real
  use mpm_bodies, only: body_mesh, is_section, body_estimate
  use mpm_config_text, only: itoa, fmt_short, fmt_list, fmt_real, finite
  use mpm_config_table, only: magnitude_bounds, spec_index, beyond
  use mpm_config_scan, only: reader_t, err_var, err_missing
  implicit none
  private
  public :: check_body, check_mesh, table_count, mesh_check_max

  !> The particles of a body the reader meshes at most (the set-up meshes larger bodies, the
  !! memory budget refuses those too large)
  real(wp), parameter :: mesh_check_max = 2.0e6_wp

contains
  !> &body: the sector (full when not given), the radii and n_circ of a ring, and the rules of
  !! the other shapes (their variables that do not apply are warned of by mpm_config).
  subroutine check_body(rd, io, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(body_cfg_t), intent(inout) :: b
    integer :: parts
    if (b%sector_id == 0) then
      b%sector = sector_names(SECTOR_FULL)
      b%sector_id = SECTOR_FULL
    end if
    if (b%shape_id == SHAPE_RING) then
      if (b%r_inner > 0.0_wp .and. b%r_outer > 0.0_wp) then
        if (.not. (b%r_inner < b%r_outer)) call err_var(rd, io, 'r_inner', &
          fmt_real(b%r_inner), 'not below r_outer = '//fmt_real(b%r_outer))
      end if
      parts = 1
      if (b%sector_id == SECTOR_HALF) parts = 2
      if (b%sector_id == SECTOR_QUARTER) parts = 4
      if (b%n_circ /= 0 .and. b%n_circ < 3) then
        call err_var(rd, io, 'n_circ', itoa(b%n_circ), 'out of range')
      else if (mod(b%n_circ, parts) /= 0) then
        call err_var(rd, io, 'n_circ', itoa(b%n_circ), 'not divisible by '//itoa(parts)// &
          ' (sector = '''//trim(b%sector)//''')')
      end if
    end if
    if (b%self_contact .and. b%sector_id == SECTOR_QUARTER) call err_var(rd, io, &
      'self_contact', '.true.', 'not with sector = ''quarter'' (it meets its mirror image on '// &
      'the plane y = centre)')
    select case (b%shape_id)
    case (SHAPE_TUBE)
      call check_tube(rd, io, b)
    case (SHAPE_HONEYCOMB)
      call check_honeycomb(rd, io, b)
    case (SHAPE_WALLS)
      if (len_trim(b%walls_file) > 0) call read_walls(rd, io, b)
    end select
  end subroutine check_body

  !> A tube: 3 to 64 vertices (pairs, no gaps), a corner radius of 0 or at least t/2.
  subroutine check_tube(rd, io, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(body_cfg_t), intent(inout) :: b
    integer :: n, k, k2
    logical :: ok
    ok = .true.
    call table_count(rd, io, 'vertices', b%vertices, n, ok)
    if (.not. ok) then
      b%vertices = unset_real
      return
    end if
    if (n == 0) then
      call err_missing(rd, io, 'vertices')
    else if (mod(n, 2) /= 0 .or. n < 6) then
      call err_var(rd, io, 'vertices', fmt_list(b%vertices(1:n)), itoa(n)//' numbers: not '// &
        '3 or more x, y pairs')
    else
      b%n_vertices = n/2
      do k = 1, b%n_vertices
        k2 = modulo(k, b%n_vertices) + 1
        if (norm2(b%vertices(2*k-1:2*k) - b%vertices(2*k2-1:2*k2)) <= 0.0_wp) then
          call err_var(rd, io, 'vertices', fmt_list(b%vertices(1:n)), 'vertex '//itoa(k)// &
            ' repeats the next one')
          return
        end if
      end do
    end if
    if (b%corner_radius > 0.0_wp .and. b%thickness > 0.0_wp .and. &
        b%corner_radius < 0.5_wp*b%thickness) call err_var(rd, io, 'corner_radius', &
      fmt_real(b%corner_radius), 'below thickness/2 = '//fmt_real(0.5_wp*b%thickness)// &
      ' (the inner face would fold)')
    if (b%corner_radius > 0.0_wp .and. b%n_vertices >= 3) call check_arcs(rd, io, b)
  end subroutine check_tube

  !> The rounded corners fit their sides: a corner of radius r turning by theta takes
  !! r tan(theta/2) of each side it joins, and the two corners of a side together at most all
  !! of it.
  subroutine check_arcs(rd, io, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(body_cfg_t), intent(in) :: b
    real(wp) :: take(b%n_vertices), side(b%n_vertices), d1(2), d2(2), turn
    integer :: k, n
    n = b%n_vertices
    do k = 1, n                                  ! side k: vertex k to k + 1
      d1 = b%vertices(2*modulo(k, n)+1:2*modulo(k, n)+2) - b%vertices(2*k-1:2*k)
      d2 = b%vertices(2*modulo(k+1, n)+1:2*modulo(k+1, n)+2) - &
           b%vertices(2*modulo(k, n)+1:2*modulo(k, n)+2)
      side(k) = norm2(d1)
      turn = abs(atan2(d1(1)*d2(2) - d1(2)*d2(1), dot_product(d1, d2)))
      take(modulo(k, n) + 1) = b%corner_radius*tan(min(0.5_wp*turn, 0.5_wp*pi - 1.0e-6_wp))
    end do
    do k = 1, n
      if (take(k) + take(modulo(k, n) + 1) <= side(k)*(1.0_wp + 1.0e-9_wp)) cycle
      call err_var(rd, io, 'corner_radius', fmt_real(b%corner_radius), 'too large for side '// &
        itoa(k)//' ('//fmt_short(side(k))//' m): its two rounded corners take '// &
        fmt_short(take(k) + take(modulo(k, n) + 1))//' m of it')
      return
    end do
  end subroutine check_arcs

  !> A honeycomb: 1 to 64 cells each way, an angle that is not 0 and leaves the cells open.
  subroutine check_honeycomb(rd, io, b)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    type(body_cfg_t), intent(inout) :: b
    real(wp) :: open_h
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
    character(len=:), allocatable :: path, line, what
    character(len=1024) :: buf, msg
    real(wp) :: r(5), big, small
    real(wp), allocatable :: seg(:,:)
    integer, allocatable :: lines(:)
    integer :: k
    character(len=:), allocatable :: unit
    integer :: u, ios, ln
    call magnitude_bounds(spec_index('body', 'thickness'), big, small, unit)   ! lengths
    path = trim(b%walls_file)
    if (path(1:1) /= '/' .and. index(rd%file, '/', back=.true.) > 0) &
      path = rd%file(1:index(rd%file, '/', back=.true.))//path
    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call err_var(rd, io, 'walls_file', ''''//trim(b%walls_file)//'''', 'cannot be read ('// &
        trim(msg)//')')
      return
    end if
    allocate(seg(5, 0), lines(0))
    ln = 0
    what = ''
    do while (len(what) == 0)
      read(u, '(a)', iostat=ios) buf
      if (ios /= 0) exit
      ln = ln + 1
      line = trim(adjustl(buf))
      if (len(line) == 0) cycle
      if (line(1:1) == '#') cycle
      if (ln == 1 .and. verify(line(1:1), '0123456789+-.') /= 0) cycle    ! a header
      read(line, *, iostat=ios) r
      if (ios /= 0 .or. .not. all(abs(r) <= huge(1.0_wp))) then
        what = path//':'//itoa(ln)//': '''//line//''' is not 5 finite numbers x1, y1, x2, '// &
          'y2, thickness'
      else if (any(abs(r) > big) .or. r(5) < small) then
        what = path//':'//itoa(ln)//': beyond the limits of the program: up to '// &
          fmt_short(big)//' m in size, a thickness of at least '//fmt_short(small)//' m'
      else if (r(5) <= 0.0_wp .or. norm2(r(3:4) - r(1:2)) <= 0.0_wp) then
        what = path//':'//itoa(ln)//': a wall of zero length or thickness'
      else if (size(seg, 2) >= 4096) then
        what = 'more than 4096 walls'
      else
        seg = reshape([seg, r], [5, size(seg, 2) + 1])
        lines = [lines, ln]
      end if
    end do
    close(u)
    if (len(what) == 0 .and. size(seg, 2) == 0) what = 'has no walls'
    do k = 1, size(seg, 2)                 ! (ends closer than this are one joint: mpm_bodies)
      if (len(what) > 0) exit
      if (norm2(seg(3:4, k) - seg(1:2, k)) <= 1.0e-6_wp*minval(seg(5, :))) what = path//':'// &
        itoa(lines(k))//': a wall shorter than 1e-6 times the thinnest wall (its ends are one joint)'
    end do
    if (len(what) > 0) then
      call err_var(rd, io, 'walls_file', ''''//trim(b%walls_file)//'''', what)
      return
    end if
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
    if (.not. (is_section(b%shape_id) .or. b%shape_id == SHAPE_DISC)) return
    if (b%shape_id == SHAPE_TUBE .and. (b%n_vertices < 3 .or. b%thickness <= 0.0_wp)) return
    if (b%shape_id == SHAPE_HONEYCOMB .and. (any(b%n_cells < 1) .or. b%thickness <= 0.0_wp &
        .or. b%cell_l <= 0.0_wp .or. b%cell_h <= 0.0_wp)) return
    if (b%shape_id == SHAPE_WALLS .and. .not. allocated(b%seg)) return
    if (b%shape_id == SHAPE_DISC .and. b%r_outer <= 0.0_wp) return
    call body_estimate(b, np, nc, ext)     ! lengths in a wrong unit: refused later, unmeshed
    if (np > mesh_check_max) return
    call body_mesh(b, xc, quad, pwall, stat, msg)
    if (stat == 2) call err_var(rd, io, 'sector', ''''//trim(b%sector)//'''', msg// &
      ' through center = '//fmt_list(b%center), '''full'', or a section that is its own mirror'// &
      ' image about the planes x = center(1) (and y = center(2) for a quarter), every wall'// &
      ' that reaches them square to them')
    if (stat == 3 .and. b%shape_id == SHAPE_TUBE) call err_var(rd, io, 'vertices', &
      fmt_list(b%vertices(1:2*b%n_vertices)), 'the polygon crosses itself: '//msg, &
      'a simple polygon, counter-clockwise')
    if (stat == 3 .and. b%shape_id == SHAPE_HONEYCOMB) call err_var(rd, io, 'cell_l', &
      fmt_real(b%cell_l), msg, 'cell_l, cell_h and cell_angle whose walls meet only at their ends')
    if (stat == 3 .and. b%shape_id == SHAPE_WALLS) call err_var(rd, io, 'walls_file', &
      ''''//trim(b%walls_file)//'''', msg, 'walls that meet only at their ends')
    if (stat == 1) call err_var(rd, io, 'n_thick', itoa(b%n_thick), 'the walls cannot be '// &
      'filled with particles: '//msg, 'walls longer than their joints need, meeting at '// &
      'angles they can (n_thick even where three or more walls meet)')
  end subroutine check_mesh

  !> Number of table entries given (leading, without gaps); reports gaps and non-finite values.
  subroutine table_count(rd, io, var, t, n, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: io
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: t(:)
    integer, intent(out) :: n
    logical, intent(inout) :: ok
    integer :: k, last
    character(len=:), allocatable :: what
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
    what = beyond(spec_index(rd%occ(io)%group, var), t)
    if (len(what) > 0) then
      call err_var(rd, io, var, '', what)
      ok = .false.
      return
    end if
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
end module mpm_config_body
