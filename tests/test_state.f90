!> The state's own serialisation and the one answer to "where is this particle's material":
!! particle_corners against closed forms (area 4 |r1 x r2| = det(F) V0 of a CPDI1 parallelogram,
!! (2 half)^2 of a uGIMP square, the shared CPDI2 corners, centroid = particle position), and a
!! checkpoint record of the state (particles, walls, time, energies) read back bit for bit, a
!! record of other counts refused.
! SPDX-License-Identifier: MIT
program test_state
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: BASIS_LINEAR, BASIS_UGIMP, BASIS_CPDI1, BASIS_CPDI2
  use mpm_particles, only: particles_t, particles_allocate, rect_counts, rect_fill, &
                           particle_corners, quad_area_centroid
  use mpm_walls, only: wall_t
  use mpm_state, only: state_t, state_write, state_read
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  character(len=512) :: scratch

  call get_command_argument(1, scratch)
  if (len_trim(scratch) == 0) scratch = '.'
  call test_corners()
  call test_round_trip()
  call finish_tests('test_state')

contains

  !> A 3 x 2 rectangle of particles 0.4 x 0.3 m, the first particle sheared and stretched.
  subroutine make_particles(p)
    type(particles_t), intent(out) :: p
    integer :: np, nc
    call rect_counts(3, 2, np, nc)
    call particles_allocate(p, np, nc)
    call rect_fill(p, 0, 0, [1.0_wp, 2.0_wp], [0.4_wp, 0.3_wp], 3, 2, 1000.0_wp, &
                   [0.5_wp, -1.0_wp], 1, 1)
    p%F(:, :, 1) = reshape([1.2_wp, 0.1_wp, 0.3_wp, 0.9_wp], [2, 2])
  end subroutine make_particles

  subroutine test_corners()
    type(particles_t) :: p
    real(wp) :: xq(2, 4), area, c(2), detf
    integer :: ip
    call begin_test('particle_corners')
    call make_particles(p)
    detf = p%F(1, 1, 1)*p%F(2, 2, 1) - p%F(1, 2, 1)*p%F(2, 1, 1)
    xq = particle_corners(p, 1, BASIS_CPDI1)
    call quad_area_centroid(xq, area, c)
    call check_close(area, detf*p%vol0(1), 'CPDI1: area = det(F) V0 (4 |r1 x r2|)', rtol=1.0e-13_wp)
    call check_close(c, p%x(:, 1), 'CPDI1: centroid = particle position', rtol=1.0e-13_wp)
    do ip = 1, p%np
      xq = particle_corners(p, ip, BASIS_UGIMP)
      call quad_area_centroid(xq, area, c)
      call check_close(area, 4.0_wp*p%half(1, ip)*p%half(2, ip), 'uGIMP: area = (2 half)^2', &
                       rtol=1.0e-13_wp)
      call check_close(c, p%x(:, ip), 'uGIMP: centroid = particle position', rtol=1.0e-13_wp)
      call check(all(particle_corners(p, ip, BASIS_LINEAR) == xq), 'linear: the uGIMP square')
      xq = particle_corners(p, ip, BASIS_CPDI2)
      call check(all(xq == p%xc(:, p%corner(:, ip))), 'CPDI2: the shared corners, in order')
      call quad_area_centroid(xq, area, c)
      call check_close(area, p%vol0(ip), 'CPDI2: area = V0 (undeformed)', rtol=1.0e-13_wp)
    end do
  end subroutine test_corners

  subroutine test_round_trip()
    type(state_t) :: a, b, other
    integer :: u, stat, k
    character(len=256) :: msg
    character(len=:), allocatable :: path
    call begin_test('state_write / state_read')
    call make_particles(a%p)
    a%p%stress(:, 2) = [1.0e6_wp, -2.0e6_wp, 3.5e5_wp, 1.0_wp/3.0_wp]
    a%p%eqps(3) = 0.125_wp
    a%p%xc(:, 4) = a%p%xc(:, 4) + [1.0e-7_wp, -3.0e-9_wp]
    allocate(a%walls(2))
    a%nwall = 2
    do k = 1, 2
      a%walls(k)%point = [0.1_wp*k, -0.7_wp]
      a%walls(k)%impulse = [1.0_wp/7.0_wp, real(k, wp)]
      a%walls(k)%force = [-2.0_wp, 1.0e-300_wp]
      a%walls(k)%work = 3.0_wp/real(k, wp)
      a%walls(k)%impulse_acc = [0.25_wp, -huge(1.0_wp)]
    end do
    a%t = 1.0e-3_wp/3.0_wp
    a%step = 123456789012_i8
    a%dt = 2.0e-8_wp
    a%vmax = 12.5_wp
    a%e_kin = 1.0_wp/11.0_wp
    a%e_plastic = 7.0_wp
    a%energy_error = 0.03_wp
    a%ext_max = 4.0_wp
    path = trim(scratch)//'/test_state.bin'
    open(newunit=u, file=path, access='stream', form='unformatted', status='replace', &
         action='write', iostat=stat, iomsg=msg)
    call check(stat == 0, 'open for writing')
    call state_write(a, u, stat, msg)
    call check(stat == 0, 'state_write')
    close(u)
    ! read into a state set up like the input would (same counts, other values)
    call make_particles(b%p)
    allocate(b%walls(2))
    b%nwall = 2
    open(newunit=u, file=path, access='stream', form='unformatted', status='old', &
         action='read', iostat=stat, iomsg=msg)
    call state_read(b, u, stat, msg)
    close(u)
    call check(stat == 0, 'state_read')
    call check(all(b%p%x == a%p%x) .and. all(b%p%v == a%p%v) .and. all(b%p%F == a%p%F) .and. &
               all(b%p%stress == a%p%stress) .and. all(b%p%eqps == a%p%eqps) .and. &
               all(b%p%xc == a%p%xc) .and. all(b%p%corner == a%p%corner) .and. &
               all(b%p%mass == a%p%mass) .and. all(b%p%vol0 == a%p%vol0), 'particles')
    do k = 1, 2
      call check(all(b%walls(k)%point == a%walls(k)%point) .and. &
                 all(b%walls(k)%impulse == a%walls(k)%impulse) .and. &
                 all(b%walls(k)%force == a%walls(k)%force) .and. &
                 b%walls(k)%work == a%walls(k)%work .and. &
                 all(b%walls(k)%impulse_acc == a%walls(k)%impulse_acc), 'wall state')
    end do
    call check(b%t == a%t .and. b%step == a%step .and. b%dt == a%dt .and. &
               b%vmax == a%vmax, 'time, step, time step, speed')
    call check(b%e_kin == a%e_kin .and. b%e_plastic == a%e_plastic .and. &
               b%energy_error == a%energy_error .and. b%ext_max == a%ext_max, 'energies')
    ! a state with one wall fewer refuses the record
    call make_particles(other%p)
    allocate(other%walls(1))
    other%nwall = 1
    open(newunit=u, file=path, access='stream', form='unformatted', status='old', &
         action='read', iostat=stat, iomsg=msg)
    call state_read(other, u, stat, msg)
    close(u, status='delete')
    call check(stat == -1, 'another wall count is refused (stat = -1)')
  end subroutine test_round_trip
end program test_state
