!> Step 1 of docs/method.md: the node block, weights and gradients of every particle (the
!! basis cache that every transfer of the step reuses), and the grid fitted around the blocks.
! SPDX-License-Identifier: MIT
module mpm_weights
  use mpm_kinds, only: wp
  use mpm_constants, only: EXIT_NUMERIC, BASIS_LINEAR, BASIS_UGIMP, BASIS_CPDI1, BASIS_CPDI2
  use mpm_grid, only: grid_t, grid_grow
  use mpm_basis, only: weights_linear, weights_ugimp, weights_cpdi1, weights_cpdi2
  use mpm_particles, only: basis_block
  use mpm_state, only: params_t, state_t, work_t, diag_t, chunk, state_context
  use mpm_strings, only: itoa, rtoa
  implicit none
  private
  public :: weights_compute

contains

  !> Step 1: block, weights and gradients of every particle; grows the block width and the
  !! grid as needed; detects folded CPDI2 domains and particles leaving a fixed grid.
  subroutine weights_compute(prm, st, g, wk, diag, stat, errmsg)
    type(params_t), intent(in) :: prm      !! parameters (basis)
    type(state_t), intent(in) :: st        !! state (particles; time for the messages)
    type(grid_t), intent(inout) :: g       !! grid (grown when the blocks leave it)
    type(work_t), intent(inout) :: wk      !! basis cache
    type(diag_t), intent(inout) :: diag    !! smallest corner Jacobian, growth count
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(inout) :: errmsg  !! what failed (set on failure)
    integer :: ip, ic, nchunk, need_max, lo(2), hi(2), add(4), bad, attempt, nb, nx, ny
    real(wp) :: origin(2), h, jmin_all
    stat = 0
    if (wk%nb == 0) then
      wk%nb = basis_block(prm%basis, 0.0_wp, g%h)
      call allocate_cache(wk, st%p%np)
    end if
    do attempt = 1, 8
      origin = g%origin
      h = g%h
      nb = wk%nb
      nx = g%nx
      ny = g%ny
      need_max = 0
      lo = huge(1)
      hi = -huge(1)
      jmin_all = huge(1.0_wp)
      bad = 0
      nchunk = (st%p%np + chunk - 1)/chunk
      !$omp parallel do default(none) schedule(static) shared(prm, st, wk, origin, h, nb, nchunk) &
      !$omp   private(ic) reduction(max: need_max, bad, hi) reduction(min: lo, jmin_all) &
      !$omp   if(wk%par)
      do ic = 1, nchunk
        call basis_kernel(1 + (ic - 1)*chunk, min(ic*chunk, st%p%np), st%p%np, st%p%nc, &
               prm%basis, nb, origin, h, st%p%x, st%p%half, st%p%F, st%p%r10, st%p%r20, &
               st%p%corner, st%p%xc, wk%blk, wk%w, wk%gw, need_max, lo, hi, bad, jmin_all)
      end do
      !$omp end parallel do
      if (prm%basis == BASIS_CPDI2) diag%jmin_seen = min(diag%jmin_seen, jmin_all)
      if (bad > 0) then
        stat = EXIT_NUMERIC
        errmsg = 'folded CPDI2 domain: the domain of particle '//itoa(bad)//' at ('// &
          rtoa(st%p%x(1, bad))//', '//rtoa(st%p%x(2, bad))//') m folded or inverted '// &
          '(corner Jacobian <= 0) at '//state_context(st, prm, g%h)//'. Remedy: near full '// &
          'crush (the side hinges close; a fast crush with n_thick = 2 folds from delta/D = '// &
          '0.85) stop the crush at delta/D <= 0.8, or use '// &
          'basis = ''cpdi1'' or ''ugimp'' (their domains cannot fold); otherwise a smaller cfl '// &
          'and more particles through the wall (docs/stability.md)'
        return
      end if
      if (need_max > wk%nb) then          ! domains grew: widen the blocks and redo
        wk%nb = need_max
        call allocate_cache(wk, st%p%np)
        cycle
      end if
      if (all(lo >= 0) .and. hi(1) <= nx - 1 .and. hi(2) <= ny - 1) return
      if (g%fixed) then
        bad = 0
        do ip = 1, st%p%np
          if (any(wk%blk(:, ip) < 0) .or. wk%blk(1, ip) + wk%nb - 1 > nx - 1 .or. &
              wk%blk(2, ip) + wk%nb - 1 > ny - 1) then
            bad = ip
            exit
          end if
        end do
        bad = max(bad, 1)
        stat = EXIT_NUMERIC
        errmsg = 'particle '//itoa(bad)//' at ('//rtoa(st%p%x(1, bad))//', '// &
          rtoa(st%p%x(2, bad))//') m left the grid at '//state_context(st, prm, g%h)// &
          '. Remedy: '// &
          'enlarge &grid lower/upper, or omit them so that the grid is fitted and grows '// &
          'with the material; if the particle flew off, the time step was unstable: lower cfl'
        return
      end if
      ! enlarge the grid by what is missing plus a margin (the grid holds no state)
      add(1) = max(0, -lo(1)); add(2) = max(0, -lo(2))
      add(3) = max(0, hi(1) - (nx - 1)); add(4) = max(0, hi(2) - (ny - 1))
      where (add > 0) add = add + 2 + max(nx, ny)/10
      if (real(nx + add(1) + add(3), wp)*real(ny + add(2) + add(4), wp) > prm%max_nodes) then
        stat = EXIT_NUMERIC
        errmsg = 'the grid would grow to '//itoa(nx + add(1) + add(3))//' x '// &
          itoa(ny + add(2) + add(4))//' nodes at '//state_context(st, prm, g%h)// &
          ', more than the memory available holds (about '//itoa(nint(prm%max_nodes))// &
          ' nodes): the material reaches from node ('//itoa(lo(1))//', '//itoa(lo(2))// &
          ') to ('//itoa(hi(1))//', '//itoa(hi(2))//') of a '//itoa(nx)//' x '//itoa(ny)// &
          ' grid. Remedy: if particles flew off, the time step was unstable: lower cfl; '// &
          'otherwise a coarser &grid h, or a shorter t_end for bodies that travel far'
        return
      end if
      call grid_grow(g, add)
      diag%grown = diag%grown + 1
    end do
    stat = EXIT_NUMERIC
    errmsg = 'non-finite positions: could not fit the grid to the particles at '// &
             state_context(st, prm, g%h)//'. Remedy: lower cfl (the time step is above the '// &
             'stable limit)'
  end subroutine weights_compute

  !> Step 1 for particles ip0..ip1: block, weights and gradients; the largest block width
  !! needed, the node range touched, the last folded CPDI2 domain and the smallest corner
  !! Jacobian ratio (all merged into the caller's values).
  subroutine basis_kernel(ip0, ip1, np, nc, basis, nb, origin, h, x, half, F, r10, r20, &
                          corner, xc, blk, w, gw, need_max, lo, hi, bad, jmin_all)
    integer, intent(in) :: ip0, ip1        !! particles
    integer, intent(in) :: np, nc          !! particles, corners
    integer, intent(in) :: basis           !! BASIS_* code
    integer, intent(in) :: nb              !! block width [nodes]
    real(wp), intent(in) :: origin(2)      !! grid origin [m]
    real(wp), intent(in) :: h              !! cell size [m]
    real(wp), intent(in) :: x(2, np)       !! positions [m]
    real(wp), intent(in) :: half(2, np)    !! uGIMP half sizes [m]
    real(wp), intent(in) :: F(2, 2, np)    !! deformation gradients [-]
    real(wp), intent(in) :: r10(2, np), r20(2, np)  !! initial CPDI1 half-vectors [m]
    integer, intent(in) :: corner(4, np)   !! corner ids
    real(wp), intent(in) :: xc(2, nc)      !! corner positions [m]
    integer, intent(out) :: blk(2, np)     !! lower-left node of each block
    real(wp), intent(out) :: w(nb*nb, np)  !! weights [-]
    real(wp), intent(out) :: gw(2, nb*nb, np)  !! gradients [1/m]
    integer, intent(inout) :: need_max     !! largest block width needed
    integer, intent(inout) :: lo(2), hi(2) !! node range touched
    integer, intent(inout) :: bad          !! last particle with a folded CPDI2 domain (or 0)
    real(wp), intent(inout) :: jmin_all    !! smallest CPDI2 corner Jacobian ratio [-]
    integer :: ip, need
    real(wp) :: xq(2, 4), jmin
    do ip = ip0, ip1
      select case (basis)
      case (BASIS_LINEAR)
        call weights_linear(x(:, ip), origin, h, nb, blk(1, ip), blk(2, ip), w(:, ip), &
                            gw(:, :, ip), need)
      case (BASIS_UGIMP)
        call weights_ugimp(x(:, ip), half(:, ip), origin, h, nb, blk(1, ip), blk(2, ip), &
                           w(:, ip), gw(:, :, ip), need)
      case (BASIS_CPDI1)
        call weights_cpdi1(x(:, ip), matmul(F(:, :, ip), r10(:, ip)), &
                           matmul(F(:, :, ip), r20(:, ip)), origin, h, nb, blk(1, ip), &
                           blk(2, ip), w(:, ip), gw(:, :, ip), need)
      case default
        xq(:, 1) = xc(:, corner(1, ip))      ! particle_corners, inline: this loop is hot
        xq(:, 2) = xc(:, corner(2, ip))
        xq(:, 3) = xc(:, corner(3, ip))
        xq(:, 4) = xc(:, corner(4, ip))
        call weights_cpdi2(xq, origin, h, nb, blk(1, ip), blk(2, ip), w(:, ip), gw(:, :, ip), &
                           need, jmin)
        if (.not. jmin > 0.0_wp) bad = max(bad, ip)
        jmin_all = min(jmin_all, jmin)
      end select
      need_max = max(need_max, need)
      lo = min(lo, blk(:, ip))
      ! the transfers run over the whole nb x nb block (zero weights past `need`), so the
      ! grid must hold all of it, not just the part this particle needs
      hi = max(hi, blk(:, ip) + max(nb, need) - 1)
    end do
  end subroutine basis_kernel

  !> (Re)allocate the per-step basis cache for the current block width, and (once) the
  !! per-particle work arrays.
  subroutine allocate_cache(wk, np)
    type(work_t), intent(inout) :: wk      !! basis cache and work arrays
    integer, intent(in) :: np              !! particles
    if (allocated(wk%w)) deallocate(wk%w, wk%gw, wk%blk)
    allocate(wk%blk(2, np), wk%w(wk%nb*wk%nb, np), wk%gw(2, wk%nb*wk%nb, np))
    if (.not. allocated(wk%tile)) then
      allocate(wk%tile(np), wk%perm(np), &
               wk%chunk_sum(3, (np + chunk - 1)/chunk))
    end if
  end subroutine allocate_cache
end module mpm_weights
