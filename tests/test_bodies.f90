!> The body shapes of mpm_bodies against closed forms, for rings (full, half, quarter; n_circ
!! automatic and given) and rectangles: the particles body_fill makes number what body_counts
!! says and the real-valued body_estimate of the memory budget says; their areas add up to the
!! polygon's closed form (ring: n/2 sin(2 pi/n) (r_o^2 - r_i^2) over the sector's share, which
!! is below pi (r_o^2 - r_i^2) by the chords; rectangle: a b) and their masses to rho times it;
!! every corner lies in body_box; and body_report names the counts.
! SPDX-License-Identifier: MIT
program test_bodies
  use mpm_kinds, only: wp
  use mpm_constants, only: pi, SHAPE_RING, SHAPE_RECT, SECTOR_FULL, SECTOR_HALF, SECTOR_QUARTER
  use mpm_particles, only: particles_t, particles_allocate
  use mpm_bodies, only: body_cfg_t, body_counts, body_fill, body_box, body_estimate, body_report
  use testing, only: begin_test, check, check_close, finish_tests
  implicit none
  type(body_cfg_t) :: b
  integer :: sector, n_circ

  do sector = SECTOR_FULL, SECTOR_QUARTER
    do n_circ = 0, 48, 48
      b = body_cfg_t()
      b%shape_id = SHAPE_RING
      b%sector_id = sector
      b%center = [0.01_wp, -0.02_wp]
      b%r_inner = 0.02395_wp
      b%r_outer = 0.02543_wp
      b%n_thick = 3
      b%n_circ = n_circ
      b%material_id = 1
      call check_body(b)
    end do
  end do
  b = body_cfg_t()
  b%shape_id = SHAPE_RECT
  b%sector_id = SECTOR_FULL
  b%center = [0.3_wp, 0.1_wp]
  b%size = [0.06_wp, 0.004_wp]
  b%n_x = 30
  b%n_y = 4
  b%material_id = 1
  call check_body(b)
  call finish_tests('test_bodies')

contains

  subroutine check_body(b)
    type(body_cfg_t), intent(in) :: b
    type(particles_t) :: p
    integer :: np, nc, nk, parts
    real(wp) :: enp, enc, ext, lo(2), hi(2), area, tol
    real(wp), parameter :: rho = 2700.0_wp
    character(len=512) :: line
    character(len=16) :: word
    call begin_test('shape '//trim(merge('ring', 'rect', b%shape_id == SHAPE_RING))// &
                    ' sector '//achar(48 + b%sector_id)//' n_circ '//achar(48 + b%n_circ/48))
    call body_counts(b, np, nc, nk)
    call body_estimate(b, enp, enc, ext)
    call check(enp == real(np, wp) .and. enc == real(nc, wp), 'body_estimate = body_counts')
    call particles_allocate(p, np, nc)
    call body_fill(p, 0, 0, b, 7, rho)
    call check(all(p%body == 7) .and. all(p%mat == 1), 'every particle has the body and material')
    if (b%shape_id == SHAPE_RING) then
      parts = 1
      if (b%sector_id == SECTOR_HALF) parts = 2
      if (b%sector_id == SECTOR_QUARTER) parts = 4
      if (b%n_circ > 0) call check(nk*parts == b%n_circ, 'n_circ particles around the ring')
      area = 0.5_wp*real(nk*parts, wp)*sin(2.0_wp*pi/real(nk*parts, wp)) &
             *(b%r_outer**2 - b%r_inner**2)/real(parts, wp)
      call check(np == b%n_thick*nk, 'n_thick x nk particles')
    else
      area = b%size(1)*b%size(2)
      call check(np == b%n_x*b%n_y, 'n_x x n_y particles')
    end if
    call check_close(sum(p%vol0), area, 'the areas add up to the closed form', rtol=1.0e-12_wp)
    call check_close(sum(p%mass), rho*area, 'the masses add up to rho x area', rtol=1.0e-12_wp)
    call body_box(b, lo, hi)
    tol = 1.0e-12_wp*maxval(abs(hi - lo))
    call check(all(p%xc(1, :) >= lo(1) - tol) .and. all(p%xc(2, :) >= lo(2) - tol) .and. &
               all(p%xc(1, :) <= hi(1) + tol) .and. all(p%xc(2, :) <= hi(2) + tol), &
               'every corner lies in body_box')
    call check(ext >= maxval(2.0_wp*p%half) - tol, 'body_estimate''s extent >= every particle side')
    line = body_report(b, 5)
    write(word, '(i0)') np
    call check(index(line, 'body 5: ') == 1 .and. &
               index(line, ', '//trim(word)//' particles (') > 0, &
               'body_report names the body and its particles: '//trim(line))
  end subroutine check_body

end program test_bodies
