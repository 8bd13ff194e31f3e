!> The input checks of a filler (`&body shape = 'filler'`: the tube it fills, whose geometry it
!! takes, and whether its particles can be made) and of bonded bodies (`&contact law =
!! 'bonded'`: basis 'cpdi2', whose shared domain corners mpm_body_tie ties).
! SPDX-License-Identifier: MIT
!
! A filler names the tube it fills (`fills`, a 'tube' given before it); the tube's centreline,
! thickness, corner radius, n_thick, centre and sector are copied into the filler's body_cfg_t
! here, once every &body is read, so that mpm_bodies can make its particles from its own record
! (mpm_sections, filler_mesh). Refused with the group, the variable and what to change: `fills`
! naming no earlier body or not a 'tube', a `center` other than the tube's, an inner face that is
! not convex, a `fill_gap` that closes an edge of it (with the largest gap allowed).
module mpm_fillers
  use mpm_kinds, only: wp
  use mpm_constants, only: SHAPE_TUBE, SHAPE_FILLER, shape_names, CONTACT_BONDED, BASIS_CPDI2
  use mpm_config_types, only: config_t
  use mpm_config_text, only: itoa, fmt_vec, fmt_real
  use mpm_config_lexer, only: reader_t
  use mpm_config_values, only: err_var
  use mpm_bodies, only: body_mesh
  implicit none
  private
  public :: filler_checks

contains

  !> A filler fills a 'tube' given before it (`fills`): the tube's centreline, thickness,
  !! corner radius, n_thick, centre and sector become the filler's (its own centre, if given,
  !! must be the tube's), then its particles must be possible (mpm_filler, filler_mesh:
  !! a convex inner face, a gap that closes none of its edges); and the 'bonded' bodies.
  subroutine filler_checks(rd, cfg, occ_body, occ_con)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(inout) :: cfg
    integer, intent(in) :: occ_body(:), occ_con(:)
    integer :: k, j, io, stat
    real(wp), allocatable :: xc(:,:)
    integer, allocatable :: quad(:,:), pwall(:)
    character(len=:), allocatable :: msg
    do k = 1, size(cfg%bodies)
      io = occ_body(k)
      if (.not. rd%occ(io)%ok .or. cfg%bodies(k)%shape_id /= SHAPE_FILLER) cycle
      associate (b => cfg%bodies(k))
        j = b%fills
        if (j < 1 .or. j >= k) then
          call err_var(rd, io, 'fills', itoa(j), 'not a &body given before this one (this '// &
            'is &body #'//itoa(k)//')', 'the number of a &body of shape ''tube'' given '// &
            'before this one')
          cycle
        end if
        if (.not. rd%occ(occ_body(j))%ok) cycle      ! (its own errors are reported)
        if (cfg%bodies(j)%shape_id /= SHAPE_TUBE) then
          call err_var(rd, io, 'fills', itoa(j), '&body #'//itoa(j)//' is a '''// &
            trim(shape_names(cfg%bodies(j)%shape_id))//''', not a ''tube''', 'the number '// &
            'of a &body of shape ''tube'' given before this one')
          cycle
        end if
        if (any(b%center /= 0.0_wp) .and. any(b%center /= cfg%bodies(j)%center)) then
          call err_var(rd, io, 'center', fmt_vec(b%center), 'not the centre of the tube it '// &
            'fills, &body #'//itoa(j)//' ('//fmt_vec(cfg%bodies(j)%center)//')', &
            'not given (a filler takes its tube''s), or the tube''s')
          cycle
        end if
        b%center = cfg%bodies(j)%center
        b%sector = cfg%bodies(j)%sector
        b%sector_id = cfg%bodies(j)%sector_id
        b%vertices = cfg%bodies(j)%vertices
        b%n_vertices = cfg%bodies(j)%n_vertices
        b%thickness = cfg%bodies(j)%thickness
        b%corner_radius = cfg%bodies(j)%corner_radius
        b%host_n_thick = cfg%bodies(j)%n_thick
        call body_mesh(b, xc, quad, pwall, stat, msg)
        if (stat == 0) cycle
        if (index(msg, 'fill_gap') > 0) then
          call err_var(rd, io, 'fill_gap', fmt_real(b%fill_gap), msg, 'a gap >= 0 that '// &
            'closes no edge of the inner face')
        else
          call err_var(rd, io, 'fills', itoa(j), 'the tube cannot be filled: '//msg, &
            'a &body of shape ''tube'' whose inner face is convex')
        end if
      end associate
    end do
    call bonded_checks(rd, cfg, occ_con)
  end subroutine filler_checks

  !> 'bonded' bodies need basis 'cpdi2': the ties join the shared domain corners of the two
  !! surfaces (mpm_body_tie).
  subroutine bonded_checks(rd, cfg, occ_con)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: occ_con(:)
    integer :: k
    do k = 1, size(cfg%contacts)
      if (.not. rd%occ(occ_con(k))%ok) cycle
      if (cfg%contacts(k)%law_id == CONTACT_BONDED .and. cfg%solver%basis_id /= BASIS_CPDI2 &
          .and. cfg%solver%basis_id > 0) call err_var(rd, occ_con(k), 'law', '''bonded''', &
        'ties the shared domain corners of the two surfaces, which only &solver basis = '// &
        '''cpdi2'' has (basis = '''//trim(cfg%solver%basis)//''')', '''frictionless'', '// &
        '''coulomb'' or ''stick'', or basis = ''cpdi2''')
    end do
  end subroutine bonded_checks
end module mpm_fillers
