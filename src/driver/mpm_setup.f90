!> Build the simulation from the case: materials, bodies, walls (with sector mirror planes),
!! fitted grid, initial energies (the derived set-up as text: mpm_report).
! SPDX-License-Identifier: MIT
module mpm_setup
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: EXIT_INPUT, SHAPE_RING, SECTOR_FULL, SECTOR_HALF, &
                           SECTOR_QUARTER, CONTACT_SLIP, VOLUMETRIC_STANDARD, &
                           CONTACT_FRICTIONLESS, CONTACT_BONDED
  use mpm_config, only: config_t, scene_of, stiffest_penalty
  use mpm_particles, only: particles_allocate, basis_reach
  use mpm_bodies, only: body_counts, body_fill, body_fields, body_field_split, is_section, &
                        has_sector, bodies_wall_ppc
  use mpm_grid, only: grid_init
  use mpm_tiles, only: tiles_init
  use mpm_walls, only: wall_t, wall_stroke_setup
  use mpm_material, only: material_from, material_wave_speed
  use mpm_solver, only: sim_t, solver_init_energy
  use mpm_errors, only: append_msg
  use mpm_strings, only: itoa, rtoa
  use mpm_weights, only: weights_compute
  use mpm_time_step, only: cfl_auto
  use mpm_budget, only: budget_t, budget_estimate, budget_check, budget_threads, &
                        budget_max_nodes, bytes_text, contact_fields
  use mpm_self_contact, only: self_contact_split
  use mpm_contact, only: contact_tie
  use mpm_sys, only: sys_memory_available
  use mpm_body_tie, only: body_tie_make
  use mpm_body_contact, only: pair_index
  implicit none
  private
  public :: setup_sim, sector_factor

contains

  !> Output factor from the modelled sector to the full ring: 1, 2 or 4.
  pure function sector_factor(cfg) result(f)
    type(config_t), intent(in) :: cfg      !! the case
    real(wp) :: f
    integer :: ib
    f = 1.0_wp
    do ib = 1, size(cfg%bodies)
      if (.not. has_sector(cfg%bodies(ib)%shape_id)) cycle
      if (cfg%bodies(ib)%sector_id == SECTOR_HALF) f = 2.0_wp
      if (cfg%bodies(ib)%sector_id == SECTOR_QUARTER) f = 4.0_wp
    end do
  end function sector_factor

  !> Create particles, walls, materials and grid from a validated case.
  subroutine setup_sim(cfg, s, stat, errmsg)
    type(config_t), intent(in) :: cfg      !! the case (validated)
    type(sim_t), intent(out) :: s          !! the simulation at t = 0
    integer, intent(out) :: stat           !! 0 or EXIT_INPUT
    character(len=:), allocatable, intent(out) :: errmsg  !! what is inconsistent
    integer :: ib, im, k, np, nc, npb, ncb, nk, sector_id
    real(wp) :: lo(2), hi(2), anchor(2), mirror_at(2), rho, margin, avail
    type(wall_t), allocatable :: walls(:)
    type(budget_t) :: bud
    character(len=:), allocatable :: source
    logical :: known
    stat = 0
    errmsg = ''
    ! what the case will need, against what the machine has, before anything is allocated
    bud = budget_estimate(cfg, budget_threads(cfg))
    call sys_memory_available(avail, source, known)
    call budget_check(cfg, bud, avail, source, known, stat, errmsg)
    if (stat /= 0) return
    s%prm%max_nodes = budget_max_nodes(bud, avail, known)
    ! materials, with the density scaled for quasi-static runs
    allocate(s%prm%mats(size(cfg%materials)))
    do im = 1, size(cfg%materials)
      associate (m => cfg%materials(im))
        s%prm%mats(im) = material_from(m, cfg%solver%mass_scale)
        s%prm%c_max = max(s%prm%c_max, material_wave_speed(s%prm%mats(im)))
      end associate
    end do
    ! bodies: one sector kind for all rings (outputs are scaled to the full ring)
    sector_id = SECTOR_FULL
    np = 0
    nc = 0
    do ib = 1, size(cfg%bodies)
      associate (b => cfg%bodies(ib))
        if (has_sector(b%shape_id)) then
          if (b%sector_id /= SECTOR_FULL) then
            if (sector_id /= SECTOR_FULL .and. sector_id /= b%sector_id) then
              call append_msg(errmsg, trim(cfg%file)//': &body #'//itoa(ib)// &
                ': sector = '''//trim(b%sector)//''': all ring bodies must use the same '// &
                'sector; allowed: one of full, half, quarter for every ring')
              stat = EXIT_INPUT
            end if
            sector_id = b%sector_id
          end if
        end if
        call body_counts(b, npb, ncb, nk)
        if (npb == 0) then                 ! a mesh the reader's check left to here
          call append_msg(errmsg, trim(cfg%file)//': &body #'//itoa(ib)//': its section '// &
            'cannot be meshed (walls too thin or too short for their joints); allowed: walls '// &
            'longer than their joints need, at n_thick particles through each')
          stat = EXIT_INPUT
        end if
        np = np + npb
        nc = nc + ncb
      end associate
    end do
    if (stat /= 0) return
    call particles_allocate(s%p, np, nc)
    np = 0
    nc = 0
    do ib = 1, size(cfg%bodies)
      associate (b => cfg%bodies(ib))
        rho = cfg%materials(b%material_id)%rho*cfg%solver%mass_scale
        call body_fill(s%p, np, nc, b, ib, rho)
        call body_counts(b, npb, ncb, nk)
        np = np + npb
        nc = nc + ncb
      end associate
    end do
    call setup_fields(cfg, s)
    ! walls: the input's, then the mirror planes of the sector (if not given already)
    call setup_walls(cfg, sector_id, walls)
    call move_alloc(walls, s%walls)
    s%nwall = size(s%walls)
    do k = 1, s%nwall
      s%walls(k)%point = s%walls(k)%point0
    end do
    call setup_params(cfg, s)
    ! grid: given bounds, or the bodies' extent plus two cells (it grows when material leaves)
    if (cfg%grid%fitted) then
      lo = minval(s%p%xc, dim=2)
      hi = maxval(s%p%xc, dim=2)
      margin = 2.0_wp*cfg%grid%h + basis_reach(s%prm%basis, maxval(s%p%half))
      lo = lo - margin
      hi = hi + margin
      anchor = cfg%bodies(1)%center
      if (sector_id /= SECTOR_FULL) anchor = first_sector_center(cfg)
      call grid_init(s%g, lo, hi, cfg%grid%h, anchor, s%prm%nf)
      s%g%fixed = .false.
    else
      ! the given bounds, rounded outward to whole cells of a lattice through `lower`, or
      ! through the mirror planes of a half or quarter model (a node line on each plane)
      anchor = cfg%grid%lower
      mirror_at = first_sector_center(cfg)
      if (sector_id /= SECTOR_FULL) anchor(1) = mirror_at(1)      ! the plane x = cx
      if (sector_id == SECTOR_QUARTER) anchor(2) = mirror_at(2)   ! and y = cy
      call grid_init(s%g, cfg%grid%lower, cfg%grid%upper, cfg%grid%h, anchor, s%prm%nf)
      s%g%fixed = .true.
      call fixed_grid_fits(cfg, s, stat, errmsg)
      if (stat /= 0) return
    end if
    call tiles_init(s%tiles, s%g)
    call body_ties(cfg, s)                                 ! 'bonded' bodies: from t = 0
    call contact_tie(s%prm, s%state_t, cfg%grid%h, s%wk)   ! 'bonded' walls: from t = 0 (also
    call solver_init_energy(s)                             ! on a restart: the same ties)
  end subroutine setup_sim

  !> The solver parameters copied from the case (immutable in the step).
  subroutine setup_params(cfg, s)
    type(config_t), intent(in) :: cfg      !! the case (validated)
    type(sim_t), intent(inout) :: s        !! the simulation: s%prm set
    s%prm%basis = cfg%solver%basis_id
    s%prm%scheme = cfg%solver%scheme_id
    s%prm%plane = cfg%solver%plane_id
    s%prm%volumetric = max(cfg%solver%volumetric_id, VOLUMETRIC_STANDARD)
    s%prm%flip = cfg%solver%flip
    s%prm%damping = cfg%solver%damping
    s%prm%deterministic = cfg%solver%deterministic
    s%prm%cfl = cfg%run%cfl                ! the input's, or the automatic value (cfl = 0)
    if (.not. s%prm%cfl > 0.0_wp) s%prm%cfl = cfl_auto(cfg%solver%basis_id, &
      cfg%solver%scheme_id, bodies_wall_ppc(cfg%bodies, cfg%grid%h), scene_of(cfg) == 'crush', &
      stiffest_penalty(cfg))
    s%prm%dt_fixed = cfg%run%dt
    s%prm%t_end = cfg%run%t_end
    s%prm%gravity = cfg%run%gravity
  end subroutine setup_params

  !> Contact between bodies (mpm_body_contact): with several bodies, one velocity field per
  !! body (the field of every particle and corner), and a second one for the lower half of a
  !! ring with self-contact (mpm_self_contact); the law of every pair of bodies: frictionless,
  !! or that of the &contact naming the pair, or of the &contact with bodies = 0, 0; a ring's
  !! halves meet frictionlessly; the pairs' impulse sums for history.csv.
  subroutine setup_fields(cfg, s)
    type(config_t), intent(in) :: cfg      !! the case
    type(sim_t), intent(inout) :: s        !! particles in place; fields, laws set
    integer :: nb, ip, a, k, i, j
    integer :: first(size(cfg%bodies))
    real(wp) :: centers(2, size(cfg%bodies))
    logical :: self(size(cfg%bodies))      ! the bodies with self-contact (contiguous)
    nb = size(cfg%bodies)
    s%prm%nbody = nb
    s%prm%nf = contact_fields(cfg)
    if (s%prm%nf < 2) return
    allocate(s%prm%field(s%p%np), s%prm%corner_field(s%p%nc), s%prm%field_body(s%prm%nf))
    k = 0
    do i = 1, nb                             ! the fields of each body, in order
      first(i) = k + 1
      centers(:, i) = cfg%bodies(i)%center
      do j = 1, body_fields(cfg%bodies(i))
        k = k + 1
        s%prm%field_body(k) = i
      end do
    end do
    s%prm%field = first(s%p%body(1:s%p%np))
    self = cfg%bodies%self_contact .and. cfg%bodies%shape_id == SHAPE_RING
    if (any(cfg%bodies%self_contact)) then
      allocate(s%prm%self_bond(s%p%np))
      call self_contact_split(s%p%x(:, 1:s%p%np), s%p%half(:, 1:s%p%np), s%p%body(1:s%p%np), &
                              self, centers, first, cfg%grid%h, &
                              s%prm%field, s%prm%self_bond)
      call section_fields(cfg, s, first)
    end if
    s%prm%corner_field = 1
    do ip = 1, s%p%np
      do a = 1, 4
        s%prm%corner_field(s%p%corner(a, ip)) = s%prm%field(ip)
      end do
    end do
    s%prm%npair = (nb*(nb - 1))/2
    allocate(s%prm%pair_law(nb, nb), s%prm%pair_mu(nb, nb))
    s%prm%pair_law = CONTACT_FRICTIONLESS
    s%prm%pair_mu = 0.0_wp
    do k = 1, size(cfg%contacts)             ! 0, 0 first: every pair not named elsewhere
      if (any(cfg%contacts(k)%bodies /= 0)) cycle
      s%prm%pair_law = cfg%contacts(k)%law_id
      s%prm%pair_mu = cfg%contacts(k)%friction
    end do
    do k = 1, size(cfg%contacts)
      i = cfg%contacts(k)%bodies(1)
      j = cfg%contacts(k)%bodies(2)
      if (i == 0) cycle
      s%prm%pair_law(i, j) = cfg%contacts(k)%law_id
      s%prm%pair_law(j, i) = cfg%contacts(k)%law_id
      s%prm%pair_mu(i, j) = cfg%contacts(k)%friction
      s%prm%pair_mu(j, i) = cfg%contacts(k)%friction
    end do
    do i = 1, nb                             ! a body is one field: no contact with itself,
      s%prm%pair_law(i, i) = 0               ! but for the halves of a ring with self-contact
      s%prm%pair_mu(i, i) = 0.0_wp
      if (cfg%bodies(i)%self_contact) s%prm%pair_law(i, i) = CONTACT_FRICTIONLESS
    end do
    allocate(s%pair_acc(3, s%prm%npair), s%pair_force(3, s%prm%npair))
    s%pair_acc = 0.0_wp
    s%pair_force = 0.0_wp
  end subroutine setup_fields

  !> The ties of the pairs of bodies with law 'bonded' (mpm_body_tie): their boundary corners
  !! within h/2 of the other's boundary at t = 0 (made again on a restart: the same ties).
  subroutine body_ties(cfg, s)
    type(config_t), intent(in) :: cfg      !! the case
    type(sim_t), intent(inout) :: s        !! particles at t = 0, laws set; the ties
    integer :: nb, i, j
    logical, allocatable :: bonded(:,:)
    integer, allocatable :: pair(:,:)
    if (s%prm%nf < 2 .or. .not. allocated(s%prm%pair_law)) return
    nb = size(cfg%bodies)
    allocate(bonded(nb, nb), pair(nb, nb))
    bonded = s%prm%pair_law == CONTACT_BONDED
    pair = 0
    do i = 1, nb
      do j = 1, nb
        if (i /= j) pair(i, j) = pair_index(i, j, nb)
      end do
    end do
    if (.not. any(bonded)) return
    call body_tie_make(s%p%xc(:, 1:s%p%nc), s%p%corner(:, 1:s%p%np), s%p%body(1:s%p%np), &
                       s%p%mass(1:s%p%np), bonded, pair, 0.5_wp*cfg%grid%h, s%prm%ties)
  end subroutine body_ties

  !> The fields of the sections with self-contact (mpm_bodies' body_field_split): each
  !! particle's field from its wall's colour, and bonded (welded to the other fields) when its
  !! centre at t = 0 lies within 2 h + 2 hmax of a seam, as a ring's seam particles are.
  subroutine section_fields(cfg, s, first)
    type(config_t), intent(in) :: cfg      !! the case
    type(sim_t), intent(inout) :: s        !! fields of the particles set
    integer, intent(in) :: first(:)        !! first field of each body
    integer :: ib, ip0, k, ip, j
    integer, allocatable :: pfield(:)
    real(wp), allocatable :: seams(:,:)
    real(wp) :: band
    ip0 = 0
    do ib = 1, size(cfg%bodies)
      k = count(s%p%body(1:s%p%np) == ib)
      if (cfg%bodies(ib)%self_contact .and. is_section(cfg%bodies(ib)%shape_id)) then
        call body_field_split(cfg%bodies(ib), pfield, seams)
        band = 2.0_wp*cfg%grid%h + 2.0_wp*maxval(s%p%half(:, ip0 + 1:ip0 + k))
        do j = 1, k
          ip = ip0 + j
          s%prm%field(ip) = first(ib) + pfield(j) - 1
          s%prm%self_bond(ip) = 0
          if (size(seams, 2) == 0) cycle
          if (minval(norm2(seams - spread(s%p%x(:, ip), 2, size(seams, 2)), dim=1)) < band) &
            s%prm%self_bond(ip) = 1
        end do
      end if
      ip0 = ip0 + k
    end do
  end subroutine section_fields

  !> A fixed grid must hold the node block of every particle at t = 0, or step 1 would stop
  !! the run ("left the grid"): step 1's own test (weights_compute) run now, refused as an
  !! input error with the bounds the blocks need.
  subroutine fixed_grid_fits(cfg, s, stat, errmsg)
    type(config_t), intent(in) :: cfg      !! the case
    type(sim_t), intent(inout) :: s        !! particles and the fixed grid (basis cache filled)
    integer, intent(out) :: stat           !! 0 or EXIT_INPUT
    character(len=:), allocatable, intent(inout) :: errmsg  !! the bounds needed
    character(len=:), allocatable :: msg, given, fix
    integer :: lo(2), hi(2)
    real(wp) :: need_lo(2), need_hi(2)
    call weights_compute(s%prm, s%state_t, s%g, s%wk, s%diag, stat, msg)
    if (stat == 0) return
    stat = EXIT_INPUT
    lo = minval(s%wk%blk(:, 1:s%p%np), dim=2)
    hi = maxval(s%wk%blk(:, 1:s%p%np), dim=2) + s%wk%nb - 1
    need_lo = s%g%origin + s%g%h*real(lo, wp)
    need_hi = s%g%origin + s%g%h*real(hi, wp)
    given = ''                             ! the bound(s) short of the support, and their fix
    fix = ''
    if (any(cfg%grid%lower > need_lo)) then
      given = 'lower = '//vec_text(cfg%grid%lower)
      fix = 'lower <= '//vec_text(need_lo)
    end if
    if (any(cfg%grid%upper < need_hi)) then
      if (len(given) > 0) given = given//', '
      if (len(fix) > 0) fix = fix//' and '
      given = given//'upper = '//vec_text(cfg%grid%upper)
      fix = fix//'upper >= '//vec_text(need_hi)
    end if
    if (len(given) == 0) then              ! (the grid's rounding to whole cells)
      given = 'lower = '//vec_text(cfg%grid%lower)//', upper = '//vec_text(cfg%grid%upper)
      fix = 'lower <= '//vec_text(need_lo)//' and upper >= '//vec_text(need_hi)
    end if
    errmsg = trim(cfg%file)//': &grid: '//given//': the grid does not hold the support of '// &
      'every particle at t = 0 (its domain plus a cell, in blocks of '//itoa(s%wk%nb)//' x '// &
      itoa(s%wk%nb)//' nodes of h = '//rtoa(s%g%h)//' m), which reaches from ('// &
      vec_text(need_lo)//') to ('//vec_text(need_hi)//') m; allowed: '//fix//', plus room '// &
      'for the motion, or lower and upper not given (the grid is fitted and grows with the '// &
      'material)'
  end subroutine fixed_grid_fits

  !> Two numbers as 'a, b' (5 significant digits).
  function vec_text(v) result(text)
    real(wp), intent(in) :: v(2)           !! the numbers
    character(len=:), allocatable :: text
    text = rtoa(v(1))//', '//rtoa(v(2))
  end function vec_text

  !> The walls of the case: the input's, then the mirror planes of a half or quarter ring.
  subroutine setup_walls(cfg, sector_id, walls)
    type(config_t), intent(in) :: cfg      !! the case
    integer, intent(in) :: sector_id       !! SECTOR_* code of the ring bodies
    type(wall_t), allocatable, intent(out) :: walls(:)  !! the walls, at t = 0
    integer :: k, j, nmirror
    real(wp) :: anchor(2)
    logical :: ok
    nmirror = 0
    if (sector_id == SECTOR_HALF) nmirror = 1
    if (sector_id == SECTOR_QUARTER) nmirror = 2
    allocate(walls(size(cfg%walls) + nmirror))
    do k = 1, size(cfg%walls)
      associate (wc => cfg%walls(k))
        walls(k)%point0 = wc%point
        walls(k)%normal = wc%normal/sqrt(dot_product(wc%normal, wc%normal))
        walls(k)%contact = wc%contact_id
        walls(k)%friction = wc%friction
        walls(k)%velocity = wc%velocity
        walls(k)%ramp = wc%ramp
        walls(k)%n_motion = wc%n_motion
        walls(k)%motion_t = wc%motion_t
        walls(k)%motion_f = wc%motion_f
        walls(k)%mirror = wc%mirror
        walls(k)%stroke = wc%stroke
        walls(k)%penalty = wc%penalty
        call wall_stroke_setup(walls(k), ok)   ! (the reader has checked that it is reached)
        if (wc%mass > 0.0_wp) then
          walls(k)%mass = wc%mass/cfg%run%depth
          walls(k)%vn = dot_product(wc%velocity, walls(k)%normal)
        end if
      end associate
    end do
    if (nmirror > 0) then
      anchor = first_sector_center(cfg)
      k = size(cfg%walls)
      walls(k + 1)%point0 = anchor
      walls(k + 1)%normal = [1.0_wp, 0.0_wp]
      walls(k + 1)%contact = CONTACT_SLIP
      walls(k + 1)%mirror = .true.
      if (nmirror == 2) then
        walls(k + 2)%point0 = anchor
        walls(k + 2)%normal = [0.0_wp, 1.0_wp]
        walls(k + 2)%contact = CONTACT_SLIP
        walls(k + 2)%mirror = .true.
      end if
    end if
    ! a wall with mass: the modelled part's share, halved by each mirror plane across it (the
    ! full structure's force on it is twice the part's, mpm_output's full_force)
    do k = 1, size(cfg%walls)
      if (.not. walls(k)%mass > 0.0_wp) cycle
      do j = 1, size(walls)
        if (j == k .or. .not. walls(j)%mirror) cycle
        if (abs(dot_product(walls(j)%normal, walls(k)%normal)) < 1.0e-6_wp) &
          walls(k)%mass = 0.5_wp*walls(k)%mass
      end do
    end do
  end subroutine setup_walls

  !> Centre of the first ring body modelled as a sector [m].
  pure function first_sector_center(cfg) result(c)
    type(config_t), intent(in) :: cfg      !! the case
    real(wp) :: c(2)
    integer :: ib
    c = 0.0_wp
    do ib = size(cfg%bodies), 1, -1
      if (has_sector(cfg%bodies(ib)%shape_id) .and. cfg%bodies(ib)%sector_id /= SECTOR_FULL) &
        c = cfg%bodies(ib)%center
    end do
  end function first_sector_center

end module mpm_setup
