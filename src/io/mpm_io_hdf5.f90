!> Particle snapshots in HDF5 (particles.h5) and the XDMF index that lets ParaView open them.
! SPDX-License-Identifier: MIT
!
! Layout (docs/output.md): /meta (attribute code_version, dataset input_nml); one group per
! snapshot /snap_NNNNNN with attributes time, step, dt, ndim, np, ncorner, and datasets
! x (np,2), v (np,2), mass (np), volume (np), stress (np,4: xx,yy,xy,zz), F (np,4: 11,21,12,22),
! eqps (np), corners (ncorner,2), quads (np,4; 0-based corner ids, counter-clockwise), and
! the 1-D copies vx, vy, sxx, syy, sxy, szz and body (np) that the XDMF index points at.
! (Fortran writes x(2,np); h5py reads it as (np, 2).) Every dataset carries `units` and
! `long_name`. The file is flushed after every snapshot, so a killed run keeps them all.
module mpm_io_hdf5
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5eset_auto_f, h5fcreate_f, h5fopen_f, &
                  h5fclose_f, &
                  h5fflush_f, h5gcreate_f, h5gclose_f, h5screate_simple_f, h5sclose_f, &
                  h5screate_f, h5dcreate_f, h5dwrite_f, h5dclose_f, h5acreate_f, h5awrite_f, &
                  h5aclose_f, h5tcopy_f, h5tset_size_f, h5tclose_f, h5lexists_f, h5ldelete_f, &
                  H5F_ACC_TRUNC_F, H5F_ACC_RDWR_F, H5F_SCOPE_GLOBAL_F, H5T_NATIVE_DOUBLE, &
                  H5T_NATIVE_INTEGER, H5T_NATIVE_CHARACTER, H5S_SCALAR_F
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: version_string, BASIS_CPDI2
  use mpm_particles, only: particles_t, particle_corners
  use mpm_strings, only: itoa
  use mpm_images, only: images_t, mirror_arrays
  implicit none
  private
  public :: snapfile_t, snap_create, snap_reopen, snap_write, snap_close, xdmf_write

  !> An open snapshot file and the list of its snapshots (for the XDMF index).
  type :: snapfile_t
    integer(hid_t) :: fid = -1             !! HDF5 file id
    character(len=512) :: path = ''        !! file path
    integer :: count = 0                   !! snapshots written
    real(wp), allocatable :: times(:)      !! their times [s]
    integer, allocatable :: nps(:), ncs(:) !! particles and corners of each (the sector's)
    type(images_t) :: images               !! mirror images written with each snapshot
  end type snapfile_t

  logical, save :: library_open = .false.

contains

  !> Turn an HDF5 error code into stat/errmsg.
  subroutine h5_check(ierr, what, stat, errmsg)
    integer, intent(in) :: ierr            !! HDF5 return code
    character(len=*), intent(in) :: what   !! call and object
    integer, intent(inout) :: stat         !! set to 1 on failure (kept if already set)
    character(len=:), allocatable, intent(inout) :: errmsg  !! set on the first failure
    if (ierr < 0 .and. stat == 0) then
      stat = 1
      errmsg = 'HDF5 call failed: '//what
      if (index(what, 'h5fcreate_f') == 1 .or. index(what, 'h5fopen_f') == 1) errmsg = &
        errmsg//' (the file is not writable, or locked: HDF5 locks its files, which a file '// &
        'system without locks refuses; there set HDF5_USE_FILE_LOCKING=FALSE)'
    end if
  end subroutine h5_check

  !> Initialise the library once.
  subroutine ensure_library(stat, errmsg)
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    integer :: ierr
    if (library_open) return
    call h5open_f(ierr)
    call h5_check(ierr, 'h5open_f', stat, errmsg)
    if (stat /= 0) return
    library_open = .true.
    ! the library's own error stack printing off: a failure is reported once, as the project's
    ! ERROR line with the call and the file (h5_check)
    call h5eset_auto_f(0, ierr)
    call h5_check(ierr, 'h5eset_auto_f', stat, errmsg)
  end subroutine ensure_library

  !> Create the file, with /meta holding the code version and the resolved input text.
  subroutine snap_create(sf, path, input_text, stat, errmsg)
    type(snapfile_t), intent(out) :: sf    !! snapshot file
    character(len=*), intent(in) :: path   !! file path
    character(len=*), intent(in) :: input_text  !! resolved namelist input
    integer, intent(out) :: stat           !! 0 or 1
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    integer(hid_t) :: gid
    integer :: ierr
    stat = 0
    errmsg = ''
    call ensure_library(stat, errmsg)
    if (stat /= 0) return
    sf%path = path
    call h5fcreate_f(path, H5F_ACC_TRUNC_F, sf%fid, ierr)
    call h5_check(ierr, 'h5fcreate_f '//trim(path), stat, errmsg)
    if (stat /= 0) return
    call h5gcreate_f(sf%fid, 'meta', gid, ierr)
    call h5_check(ierr, 'h5gcreate_f /meta', stat, errmsg)
    if (stat /= 0) return
    call write_string_attr(gid, 'code_version', 'tubempm '//version_string, stat, errmsg)
    call write_string_dataset(gid, 'input_nml', input_text, stat, errmsg)
    call h5gclose_f(gid, ierr)
    call h5_check(ierr, 'h5gclose_f /meta', stat, errmsg)
    allocate(sf%times(0), sf%nps(0), sf%ncs(0))
  end subroutine snap_create

  !> Re-open an existing file for appending after a restart; snapshots after `t_keep` are
  !! removed so that the continued run does not duplicate them.
  subroutine snap_reopen(sf, path, times, nps, ncs, stat, errmsg)
    type(snapfile_t), intent(out) :: sf    !! snapshot file
    character(len=*), intent(in) :: path   !! file path
    real(wp), intent(in) :: times(:)       !! times of the snapshots to keep [s]
    integer, intent(in) :: nps(:), ncs(:)  !! their particle and corner counts
    integer, intent(out) :: stat           !! 0 or 1
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    integer :: ierr, k
    logical :: exists
    stat = 0
    errmsg = ''
    call ensure_library(stat, errmsg)
    if (stat /= 0) return
    sf%path = path
    call h5fopen_f(path, H5F_ACC_RDWR_F, sf%fid, ierr)
    call h5_check(ierr, 'h5fopen_f '//trim(path), stat, errmsg)
    if (stat /= 0) return
    sf%count = size(times)
    sf%times = times
    sf%nps = nps
    sf%ncs = ncs
    do k = sf%count + 1, sf%count + 100000
      call h5lexists_f(sf%fid, snap_name(k), exists, ierr)
      if (ierr < 0 .or. .not. exists) exit
      call h5ldelete_f(sf%fid, snap_name(k), ierr)
      call h5_check(ierr, 'h5ldelete_f '//snap_name(k), stat, errmsg)
      if (stat /= 0) return
    end do
  end subroutine snap_reopen

  !> Name of snapshot k.
  pure function snap_name(k) result(name)
    integer, intent(in) :: k               !! snapshot number (1-based)
    character(len=11) :: name
    write(name, '(a,i6.6)') 'snap_', k - 1
  end function snap_name

  !> Append one snapshot of the particles and flush the file; with mirror images (sf%images),
  !! the whole tube once more in the subgroup `mirrored`.
  subroutine snap_write(sf, p, basis, t, step, dt, stat, errmsg)
    type(snapfile_t), intent(inout) :: sf  !! snapshot file
    type(particles_t), intent(in) :: p     !! particles
    integer, intent(in) :: basis           !! BASIS_* code (what the corners are)
    real(wp), intent(in) :: t              !! time [s]
    integer(i8), intent(in) :: step    !! step number
    real(wp), intent(in) :: dt             !! time step [s]
    integer, intent(out) :: stat           !! 0 or 1
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    integer(hid_t) :: gid
    integer :: ierr, ncorner
    real(wp), allocatable :: corners(:,:)
    integer, allocatable :: quads(:,:)
    character(len=11) :: name
    stat = 0
    errmsg = ''
    name = snap_name(sf%count + 1)
    call h5gcreate_f(sf%fid, name, gid, ierr)
    call h5_check(ierr, 'h5gcreate_f '//name, stat, errmsg)
    if (stat /= 0) return
    call write_real_attr(gid, 'time', t, stat, errmsg)
    call write_int_attr(gid, 'step', int(step), stat, errmsg)
    call write_real_attr(gid, 'dt', dt, stat, errmsg)
    call write_int_attr(gid, 'ndim', 2, stat, errmsg)
    call output_corners(p, basis, corners, quads)
    ncorner = size(corners, 2)
    call write_int_attr(gid, 'np', p%np, stat, errmsg)
    call write_int_attr(gid, 'ncorner', ncorner, stat, errmsg)
    call write_particle_data(gid, p%x, p%v, p%stress, reshape(p%F, [4, p%np]), &
      scalars(p), p%body(1:p%np), corners, quads, stat, errmsg)
    if (sf%images%n > 1) call write_mirrored(gid, sf%images, p, corners, quads, stat, errmsg)
    call h5gclose_f(gid, ierr)
    call h5_check(ierr, 'h5gclose_f '//name, stat, errmsg)
    call h5fflush_f(sf%fid, H5F_SCOPE_GLOBAL_F, ierr)
    call h5_check(ierr, 'h5fflush_f '//trim(sf%path), stat, errmsg)
    if (stat /= 0) then
      errmsg = errmsg//' (writing '//trim(sf%path)//')'
      return
    end if
    sf%count = sf%count + 1
    sf%times = [sf%times, t]
    sf%nps = [sf%nps, p%np]
    sf%ncs = [sf%ncs, ncorner]
  end subroutine snap_write

  !> The whole tube into the subgroup `mirrored` of a snapshot: the sector, then its images
  !! (mpm_images), with the attributes np, ncorner, images and mirror_x / mirror_y (the planes).
  subroutine write_mirrored(parent, im, p, corners, quads, stat, errmsg)
    integer(hid_t), intent(in) :: parent   !! the snapshot group
    type(images_t), intent(in) :: im       !! the images
    type(particles_t), intent(in) :: p     !! particles (the sector)
    real(wp), intent(in) :: corners(:,:)   !! the sector's output corners [m]
    integer, intent(in) :: quads(:,:)      !! their 0-based ids per particle
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    real(wp), allocatable :: xw(:,:), vw(:,:), sw(:,:), fw(:,:), scw(:,:), cw(:,:)
    integer, allocatable :: bw(:), qw(:,:), image(:)
    integer(hid_t) :: gid
    integer :: ierr
    if (stat /= 0) return
    call mirror_arrays(im, p%x, p%v, p%stress, reshape(p%F, [4, p%np]), scalars(p), &
      p%body(1:p%np), corners, quads, xw, vw, sw, fw, scw, bw, cw, qw, image)
    call h5gcreate_f(parent, 'mirrored', gid, ierr)
    call h5_check(ierr, 'h5gcreate_f mirrored', stat, errmsg)
    if (stat /= 0) return
    call write_int_attr(gid, 'np', size(xw, 2), stat, errmsg)
    call write_int_attr(gid, 'ncorner', size(cw, 2), stat, errmsg)
    call write_int_attr(gid, 'images', im%n, stat, errmsg)
    if (im%across(1)) call write_real_attr(gid, 'mirror_x', im%c(1), stat, errmsg)
    if (im%across(2)) call write_real_attr(gid, 'mirror_y', im%c(2), stat, errmsg)
    call write_particle_data(gid, xw, vw, sw, fw, scw, bw, cw, qw, stat, errmsg)
    call write_int_2d(gid, 'image', reshape(image, [1, size(image)]), '-', 'copy of the '// &
      'sector: 0 computed, 1 mirrored in x = mirror_x (half, quarter), 2 in y = mirror_y, '// &
      '3 in both (quarter)', stat, errmsg, flat=.true.)
    call h5gclose_f(gid, ierr)
    call h5_check(ierr, 'h5gclose_f mirrored', stat, errmsg)
  end subroutine write_mirrored

  !> mass, volume and eqps of the particles as the rows of one (3, np) array.
  pure function scalars(p) result(sc)
    type(particles_t), intent(in) :: p     !! particles
    real(wp) :: sc(3, p%np)
    sc(1, :) = p%mass(1:p%np)
    sc(2, :) = p%vol(1:p%np)
    sc(3, :) = p%eqps(1:p%np)
  end function scalars

  !> The datasets of a set of particles (docs/output.md): x, v, mass, volume, stress, F, eqps,
  !! the 1-D columns vx, vy, sxx, syy, sxy, szz and body, corners and quads.
  subroutine write_particle_data(gid, x, v, stress, F, sc, body, corners, quads, stat, errmsg)
    integer(hid_t), intent(in) :: gid      !! group
    real(wp), intent(in) :: x(:,:), v(:,:) !! position, velocity (2, np) [m, m/s]
    real(wp), intent(in) :: stress(:,:), F(:,:)  !! (4, np) [Pa, -]
    real(wp), intent(in) :: sc(:,:)        !! mass, volume, eqps (3, np)
    integer, intent(in) :: body(:)         !! body ids
    real(wp), intent(in) :: corners(:,:)   !! (2, ncorner) [m]
    integer, intent(in) :: quads(:,:)      !! (4, np) 0-based corner ids
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    real(wp), allocatable :: col(:)
    character(len=2), parameter :: xyz = 'xy'
    character(len=2), parameter :: stress_names(4) = ['xx', 'yy', 'xy', 'zz']
    integer :: k
    call write_real_2d(gid, 'x', x, 'm', 'particle position (domain centroid)', stat, errmsg)
    call write_real_2d(gid, 'v', v, 'm/s', 'particle velocity', stat, errmsg)
    col = sc(1, :)
    call write_real_1d(gid, 'mass', col, 'kg/m', 'particle mass per unit depth', stat, errmsg)
    col = sc(2, :)
    call write_real_1d(gid, 'volume', col, 'm^2', 'particle area (volume per unit depth)', &
                       stat, errmsg)
    call write_real_2d(gid, 'stress', stress, 'Pa', 'Cauchy stress xx, yy, xy, zz', stat, &
                       errmsg)
    call write_real_2d(gid, 'F', F, '-', 'deformation gradient F11, F21, F12, F22', stat, errmsg)
    col = sc(3, :)
    call write_real_1d(gid, 'eqps', col, '-', 'equivalent plastic strain', stat, errmsg)
    ! the components once more as 1-D datasets: ParaView's default XDMF reader (Xdmf3) skips
    ! hyperslabs of the 2-D ones ("unrecognized array type"), so the XDMF index points at these
    do k = 1, 2
      col = v(k, :)
      call write_real_1d(gid, 'v'//xyz(k:k), col, 'm/s', 'particle velocity '//xyz(k:k), &
                         stat, errmsg)
    end do
    do k = 1, 4
      col = stress(k, :)
      call write_real_1d(gid, 's'//stress_names(k), col, 'Pa', 'Cauchy stress '// &
                         stress_names(k), stat, errmsg)
    end do
    call write_int_2d(gid, 'body', reshape(body, [1, size(body)]), '-', &
                      'body of each particle (order of the &body groups, from 1)', stat, errmsg, &
                      flat=.true.)
    call write_real_2d(gid, 'corners', corners, 'm', 'particle domain corners', stat, errmsg)
    call write_int_2d(gid, 'quads', quads, '-', 'corner ids of each particle (0-based, ccw)', &
                      stat, errmsg)
  end subroutine write_particle_data

  !> Close the file.
  subroutine snap_close(sf, stat, errmsg)
    type(snapfile_t), intent(inout) :: sf  !! snapshot file
    integer, intent(out) :: stat           !! 0 or 1
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    integer :: ierr
    stat = 0
    errmsg = ''
    if (sf%fid < 0) return
    call h5fclose_f(sf%fid, ierr)
    call h5_check(ierr, 'h5fclose_f '//trim(sf%path), stat, errmsg)
    sf%fid = -1
  end subroutine snap_close

  !> Domain corners for output: the shared CPDI2 corners; otherwise the four corners of each
  !! particle (mpm_particles: particle_corners), not shared.
  subroutine output_corners(p, basis, corners, quads)
    type(particles_t), intent(in) :: p     !! particles
    integer, intent(in) :: basis           !! BASIS_* code
    real(wp), allocatable, intent(out) :: corners(:,:)  !! (2, ncorner) [m]
    integer, allocatable, intent(out) :: quads(:,:)     !! (4, np) 0-based ids
    integer :: ip
    if (basis == BASIS_CPDI2) then
      corners = p%xc
      quads = p%corner - 1
      return
    end if
    allocate(corners(2, 4*p%np), quads(4, p%np))
    do ip = 1, p%np
      corners(:, 4*ip - 3:4*ip) = particle_corners(p, ip, basis)
      quads(:, ip) = [4*ip - 4, 4*ip - 3, 4*ip - 2, 4*ip - 1]
    end do
  end subroutine output_corners

  !> Write the XDMF index of all snapshots: a temporal collection of quadrilateral meshes
  !! (the particle domains) with cell data; with mirror images, of the whole tube (the
  !! subgroup `mirrored` of each snapshot) with the copy number `image` as one more array.
  subroutine xdmf_write(sf, xpath, h5name, stat, errmsg)
    type(snapfile_t), intent(in) :: sf     !! snapshot file
    character(len=*), intent(in) :: xpath  !! XDMF file path
    character(len=*), intent(in) :: h5name !! HDF5 file name relative to the XDMF file
    integer, intent(out) :: stat           !! 0 or iostat
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    integer :: u, k
    character(len=512) :: msg
    character(len=:), allocatable :: g, np, nc
    integer :: n
    errmsg = ''
    open(newunit=u, file=xpath, status='replace', action='write', iostat=stat, iomsg=msg)
    if (stat /= 0) then
      errmsg = 'cannot open '//trim(xpath)//' for writing: '//trim(msg)
      return
    end if
    write(u, '(a)') '<?xml version="1.0" ?>'
    write(u, '(a)') '<Xdmf Version="3.0">'
    write(u, '(a)') ' <Domain>'
    write(u, '(a)') '  <Grid Name="particles" GridType="Collection" CollectionType="Temporal">'
    n = sf%images%n
    do k = 1, sf%count
      g = h5name//':/'//snap_name(k)
      if (n > 1) g = g//'/mirrored'
      np = itoa(n*sf%nps(k))
      nc = itoa(n*sf%ncs(k))
      write(u, '(a)') '   <Grid Name="'//snap_name(k)//'" GridType="Uniform">'
      write(u, '(a,es24.16e3,a)') '    <Time Value="', sf%times(k), '"/>'
      write(u, '(a)') '    <Topology TopologyType="Quadrilateral" NumberOfElements="'//np//'">'
      write(u, '(a)') '     <DataItem Dimensions="'//np//' 4" NumberType="Int" Precision="4"'// &
        ' Format="HDF">'//g//'/quads</DataItem>'
      write(u, '(a)') '    </Topology>'
      write(u, '(a)') '    <Geometry GeometryType="XY">'
      write(u, '(a)') '     <DataItem Dimensions="'//nc//' 2" NumberType="Float" Precision="8"'// &
        ' Format="HDF">'//g//'/corners</DataItem>'
      write(u, '(a)') '    </Geometry>'
      call scalar_attr(u, 'eqps', g//'/eqps', np)
      call scalar_attr(u, 'mass', g//'/mass', np)
      call scalar_attr(u, 'volume', g//'/volume', np)
      call scalar_attr(u, 'vx', g//'/vx', np)
      call scalar_attr(u, 'vy', g//'/vy', np)
      call scalar_attr(u, 'sxx', g//'/sxx', np)
      call scalar_attr(u, 'syy', g//'/syy', np)
      call scalar_attr(u, 'sxy', g//'/sxy', np)
      call scalar_attr(u, 'szz', g//'/szz', np)
      write(u, '(a)') '    <Attribute Name="body" AttributeType="Scalar" Center="Cell">'
      write(u, '(a)') '     <DataItem Dimensions="'//np//'" NumberType="Int" Precision="4"'// &
        ' Format="HDF">'//g//'/body</DataItem>'
      write(u, '(a)') '    </Attribute>'
      if (n > 1) then
        write(u, '(a)') '    <Attribute Name="image" AttributeType="Scalar" Center="Cell">'
        write(u, '(a)') '     <DataItem Dimensions="'//np//'" NumberType="Int" Precision="4"'// &
          ' Format="HDF">'//g//'/image</DataItem>'
        write(u, '(a)') '    </Attribute>'
      end if
      write(u, '(a)') '   </Grid>'
    end do
    write(u, '(a)') '  </Grid>'
    write(u, '(a)') ' </Domain>'
    write(u, '(a)', iostat=stat, iomsg=msg) '</Xdmf>'
    if (stat /= 0) errmsg = 'cannot write '//trim(xpath)//': '//trim(msg)
    close(u, iostat=stat, iomsg=msg)
    if (stat /= 0 .and. len(errmsg) == 0) errmsg = 'cannot close '//trim(xpath)//': '//trim(msg)
  end subroutine xdmf_write

  !> One scalar cell attribute.
  subroutine scalar_attr(u, name, ref, np)
    integer, intent(in) :: u               !! unit
    character(len=*), intent(in) :: name, ref, np  !! attribute name, HDF5 reference, count
    write(u, '(a)') '    <Attribute Name="'//name//'" AttributeType="Scalar" Center="Cell">'
    write(u, '(a)') '     <DataItem Dimensions="'//np//'" NumberType="Float" Precision="8"'// &
      ' Format="HDF">'//ref//'</DataItem>'
    write(u, '(a)') '    </Attribute>'
  end subroutine scalar_attr

  !> A real scalar attribute.
  subroutine write_real_attr(loc, name, value, stat, errmsg)
    integer(hid_t), intent(in) :: loc      !! group
    character(len=*), intent(in) :: name   !! attribute name
    real(wp), intent(in) :: value          !! value
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    integer(hid_t) :: sid, aid
    integer(hsize_t) :: dims(1) = [1_hsize_t]
    integer :: ierr
    if (stat /= 0) return
    call h5screate_f(H5S_SCALAR_F, sid, ierr)
    call h5_check(ierr, 'h5screate_f '//name, stat, errmsg)
    call h5acreate_f(loc, name, H5T_NATIVE_DOUBLE, sid, aid, ierr)
    call h5_check(ierr, 'h5acreate_f '//name, stat, errmsg)
    call h5awrite_f(aid, H5T_NATIVE_DOUBLE, value, dims, ierr)
    call h5_check(ierr, 'h5awrite_f '//name, stat, errmsg)
    call h5aclose_f(aid, ierr)
    call h5sclose_f(sid, ierr)
  end subroutine write_real_attr

  !> An integer scalar attribute.
  subroutine write_int_attr(loc, name, value, stat, errmsg)
    integer(hid_t), intent(in) :: loc      !! group
    character(len=*), intent(in) :: name   !! attribute name
    integer, intent(in) :: value           !! value
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    integer(hid_t) :: sid, aid
    integer(hsize_t) :: dims(1) = [1_hsize_t]
    integer :: ierr
    if (stat /= 0) return
    call h5screate_f(H5S_SCALAR_F, sid, ierr)
    call h5_check(ierr, 'h5screate_f '//name, stat, errmsg)
    call h5acreate_f(loc, name, H5T_NATIVE_INTEGER, sid, aid, ierr)
    call h5_check(ierr, 'h5acreate_f '//name, stat, errmsg)
    call h5awrite_f(aid, H5T_NATIVE_INTEGER, value, dims, ierr)
    call h5_check(ierr, 'h5awrite_f '//name, stat, errmsg)
    call h5aclose_f(aid, ierr)
    call h5sclose_f(sid, ierr)
  end subroutine write_int_attr

  !> A string attribute.
  subroutine write_string_attr(loc, name, value, stat, errmsg)
    integer(hid_t), intent(in) :: loc      !! group or dataset
    character(len=*), intent(in) :: name   !! attribute name
    character(len=*), intent(in) :: value  !! text
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    integer(hid_t) :: sid, aid, tid
    integer(hsize_t) :: dims(1) = [1_hsize_t]
    integer :: ierr
    if (stat /= 0) return
    call h5tcopy_f(H5T_NATIVE_CHARACTER, tid, ierr)
    call h5_check(ierr, 'h5tcopy_f '//name, stat, errmsg)
    call h5tset_size_f(tid, int(max(len(value), 1), size_t), ierr)
    call h5_check(ierr, 'h5tset_size_f '//name, stat, errmsg)
    call h5screate_f(H5S_SCALAR_F, sid, ierr)
    call h5acreate_f(loc, name, tid, sid, aid, ierr)
    call h5_check(ierr, 'h5acreate_f '//name, stat, errmsg)
    call h5awrite_f(aid, tid, value, dims, ierr)
    call h5_check(ierr, 'h5awrite_f '//name, stat, errmsg)
    call h5aclose_f(aid, ierr)
    call h5sclose_f(sid, ierr)
    call h5tclose_f(tid, ierr)
  end subroutine write_string_attr

  !> A scalar string dataset.
  subroutine write_string_dataset(loc, name, value, stat, errmsg)
    integer(hid_t), intent(in) :: loc      !! group
    character(len=*), intent(in) :: name   !! dataset name
    character(len=*), intent(in) :: value  !! text
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    integer(hid_t) :: sid, did, tid
    integer(hsize_t) :: dims(1) = [1_hsize_t]
    integer :: ierr
    if (stat /= 0) return
    call h5tcopy_f(H5T_NATIVE_CHARACTER, tid, ierr)
    call h5tset_size_f(tid, int(max(len(value), 1), size_t), ierr)
    call h5_check(ierr, 'h5tset_size_f '//name, stat, errmsg)
    call h5screate_f(H5S_SCALAR_F, sid, ierr)
    call h5dcreate_f(loc, name, tid, sid, did, ierr)
    call h5_check(ierr, 'h5dcreate_f '//name, stat, errmsg)
    call h5dwrite_f(did, tid, value, dims, ierr)
    call h5_check(ierr, 'h5dwrite_f '//name, stat, errmsg)
    call h5dclose_f(did, ierr)
    call h5sclose_f(sid, ierr)
    call h5tclose_f(tid, ierr)
  end subroutine write_string_dataset

  !> A 1-D real dataset with units and long_name.
  subroutine write_real_1d(loc, name, a, units, long_name, stat, errmsg)
    integer(hid_t), intent(in) :: loc      !! group
    character(len=*), intent(in) :: name   !! dataset name
    real(wp), intent(in) :: a(:)           !! data
    character(len=*), intent(in) :: units, long_name  !! metadata
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    integer(hid_t) :: sid, did
    integer(hsize_t) :: dims(1)
    integer :: ierr
    if (stat /= 0) return
    dims = [int(size(a), hsize_t)]
    call h5screate_simple_f(1, dims, sid, ierr)
    call h5_check(ierr, 'h5screate_simple_f '//name, stat, errmsg)
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, sid, did, ierr)
    call h5_check(ierr, 'h5dcreate_f '//name, stat, errmsg)
    call h5dwrite_f(did, H5T_NATIVE_DOUBLE, a, dims, ierr)
    call h5_check(ierr, 'h5dwrite_f '//name, stat, errmsg)
    call write_string_attr(did, 'units', units, stat, errmsg)
    call write_string_attr(did, 'long_name', long_name, stat, errmsg)
    call h5dclose_f(did, ierr)
    call h5sclose_f(sid, ierr)
  end subroutine write_real_1d

  !> A 2-D real dataset (ncomp, n) in Fortran order = (n, ncomp) in C/h5py order.
  subroutine write_real_2d(loc, name, a, units, long_name, stat, errmsg)
    integer(hid_t), intent(in) :: loc      !! group
    character(len=*), intent(in) :: name   !! dataset name
    real(wp), intent(in) :: a(:,:)         !! data
    character(len=*), intent(in) :: units, long_name  !! metadata
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    integer(hid_t) :: sid, did
    integer(hsize_t) :: dims(2)
    integer :: ierr
    if (stat /= 0) return
    dims = [int(size(a, 1), hsize_t), int(size(a, 2), hsize_t)]
    call h5screate_simple_f(2, dims, sid, ierr)
    call h5_check(ierr, 'h5screate_simple_f '//name, stat, errmsg)
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, sid, did, ierr)
    call h5_check(ierr, 'h5dcreate_f '//name, stat, errmsg)
    call h5dwrite_f(did, H5T_NATIVE_DOUBLE, a, dims, ierr)
    call h5_check(ierr, 'h5dwrite_f '//name, stat, errmsg)
    call write_string_attr(did, 'units', units, stat, errmsg)
    call write_string_attr(did, 'long_name', long_name, stat, errmsg)
    call h5dclose_f(did, ierr)
    call h5sclose_f(sid, ierr)
  end subroutine write_real_2d

  !> A 2-D integer dataset; with flat, a 1-D dataset of all its values.
  subroutine write_int_2d(loc, name, a, units, long_name, stat, errmsg, flat)
    integer(hid_t), intent(in) :: loc      !! group
    character(len=*), intent(in) :: name   !! dataset name
    integer, intent(in) :: a(:,:)          !! data
    character(len=*), intent(in) :: units, long_name  !! metadata
    integer, intent(inout) :: stat         !! status
    character(len=:), allocatable, intent(inout) :: errmsg  !! message
    logical, intent(in), optional :: flat  !! write a 1-D dataset
    integer(hid_t) :: sid, did
    integer(hsize_t) :: dims(2)
    integer :: ierr, rank
    if (stat /= 0) return
    dims = [int(size(a, 1), hsize_t), int(size(a, 2), hsize_t)]
    rank = 2
    if (present(flat)) then
      if (flat) then
        dims = [int(size(a), hsize_t), 1_hsize_t]
        rank = 1
      end if
    end if
    call h5screate_simple_f(rank, dims(1:rank), sid, ierr)
    call h5_check(ierr, 'h5screate_simple_f '//name, stat, errmsg)
    call h5dcreate_f(loc, name, H5T_NATIVE_INTEGER, sid, did, ierr)
    call h5_check(ierr, 'h5dcreate_f '//name, stat, errmsg)
    call h5dwrite_f(did, H5T_NATIVE_INTEGER, a, dims, ierr)
    call h5_check(ierr, 'h5dwrite_f '//name, stat, errmsg)
    call write_string_attr(did, 'units', units, stat, errmsg)
    call write_string_attr(did, 'long_name', long_name, stat, errmsg)
    call h5dclose_f(did, ierr)
    call h5sclose_f(sid, ierr)
  end subroutine write_int_2d
end module mpm_io_hdf5
