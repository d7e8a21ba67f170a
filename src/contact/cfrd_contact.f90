!> Contact between independent bodies (paper section 2.4, eqs. 11-17; docs/theory.md
!> section 14): slave and master surfaces of element faces, the global search (bucket grid
!> over the master segments, coordinates updated every increment so that slip may be large),
!> segment-to-segment (mortar) or node-to-segment coupling, Lagrange multipliers (the
!> contact tractions p, q at the slave nodes, eqs. 13-14) and Coulomb friction (eq. 16) with a
!> primal-dual active set: open, stick or slip per slave node.
!>
!> Each slave node c is a "contact element" of the global system: its coupling list
!> (nodes i, coefficients a_ci: +D for slave nodes, -M for master nodes) gives the weighted
!> gap g_c(v) = g_c - n_c . sum_i a_ci v_i and the weighted slip s_c(v) = t_c . sum_i a_ci v_i
!> of a displacement increment v, and the forces -a_ci (p_c n_c - q_c t_c) on its nodes.
!> Its two multiplier equations are numbered after the displacement equations. This module
!> builds the contact elements (surfaces, search, couplings, gaps); cfrd_contact_constraints
!> puts them in the system and updates their statuses.
module cfrd_contact
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, scheme_nts, search_rpim
    use cfrd_mortar, only: face_normal, mortar_segment_pair, mortar_cell_points, project_node, &
                           dual_shape
    use cfrd_rpim, only: rpim_shape, rpim_support
    use cfrd_bucket_search, only: bucket_grid_t, build_grid, query_grid
    use cfrd_contact_cast, only: cast_master_offsets
    implicit none
    private

    public :: contact_t, new_contact, contact_geometry, arc_lengths
    public :: contact_open, contact_stick, contact_slip, contact_iteration_limit

    integer, parameter :: contact_open = 0    !! not in contact (or not placed / unsupported)
    integer, parameter :: contact_stick = 1   !! closed, no slip
    integer, parameter :: contact_slip = 2    !! closed, sliding at the Coulomb limit
    !> Active-set iterations per solve before giving up (the stage driver then cuts back).
    integer, parameter :: contact_iteration_limit = 40
    !> A pair's slave is "much finer" than its master when its mean active face is this many
    !> times shorter: its slave nodes then share one friction law per master segment [choice]
    real(dp), parameter, public :: friction_group_ratio = 3.0_dp

    !> The contact state and the geometry of the current increment.
    type :: contact_t
        integer :: nc = 0                          !! slave (contact) nodes of all pairs
        integer, allocatable :: node(:)            !! (nc) mesh node
        integer, allocatable :: pair(:)            !! (nc) contact pair
        integer, allocatable :: group(:)           !! (nc) element group of its slave face
        real(dp), allocatable :: s(:)              !! (nc) m, along the slave surface
        !> slave segments: contact nodes (2, ns), element, pair
        integer, allocatable :: seg(:, :), seg_element(:)
        !> master segments: mesh nodes (2, nm), element, pair
        integer, allocatable :: mseg(:, :), mseg_element(:), mseg_pair(:)
        ! State (kept from increment to increment)
        logical, allocatable :: placed(:)          !! (nc) some slave face of it is active
        integer, allocatable :: status(:)          !! (nc) contact_open, _stick, _slip
        integer, allocatable :: slip_sign(:)       !! (nc) +-1 in slip (q = mu p sign)
        real(dp), allocatable :: p(:)              !! (nc) kPa, normal pressure (+ compression)
        real(dp), allocatable :: q(:)              !! (nc) kPa, shear traction on the slave along t
        real(dp), allocatable :: g0(:)             !! (nc) m, gap taken as closed at placement
        real(dp), allocatable :: gap(:)            !! (nc) m, gap at the last accepted state
        real(dp), allocatable :: slip(:)           !! (nc) m, accumulated slip along t
        real(dp), allocatable :: u(:, :)           !! (2, nnode) m since placement, never reset
        !> (nnode) the search at which a master node was first active (0: not yet): RPIM
        !> curves run only through nodes placed together (chain_master_segments)
        integer, allocatable :: birth(:)
        integer :: searches = 0                    !! searches made (accepted increments)
        ! Geometry of the current increment (contact_geometry)
        logical, allocatable :: supported(:)       !! (nc) coupled to the master surface
        real(dp), allocatable :: normal(:, :)      !! (2, nc) outward normal of the slave
        real(dp), allocatable :: tangent(:, :)     !! (2, nc) normal turned counter-clockwise
        real(dp), allocatable :: w(:)              !! (nc) m, sum_l D_cl
        real(dp), allocatable :: wref(:)           !! (nc) m, tributary length
        real(dp), allocatable :: g(:)              !! (nc) m*m, weighted gap at the start
        real(dp), allocatable :: g_curve(:)        !! (nc) m*m, RPIM curve's weighted offset
        !> faces active at the last search (small slip: no new search until they change)
        logical, allocatable :: seg_searched(:), mseg_searched(:)
        integer, allocatable :: cpl_ptr(:)         !! (nc + 1)
        integer, allocatable :: cpl_node(:)
        real(dp), allocatable :: cpl_a(:)
        !> Friction per master segment (a slave much finer than its master, docs/theory.md
        !> section 14): the group of each slave node (0: its own friction law), and the
        !> groups' members, contact nodes grp_node(grp_ptr(g):grp_ptr(g + 1) - 1) ascending
        integer :: ngroup = 0
        integer, allocatable :: tgroup(:)          !! (nc)
        integer, allocatable :: grp_ptr(:), grp_node(:)
        !> (nc) the shape of a group's shear traction, q_c = beta_c q_G: the members'
        !> pressures at the start of the increment over the group's largest (1 if none;
        !> cfrd_contact_constraints: contact_shear_shape)
        real(dp), allocatable :: beta(:)
    end type contact_t

contains

    !> Slave nodes, slave and master segments of every pair of the model; the state at rest.
    subroutine new_contact(model, contact)
        type(model_t), intent(in) :: model
        type(contact_t), intent(out) :: contact
        integer, allocatable :: index_of(:)
        integer :: ip, k, e, f, a, b, ns, nm, nc
        associate (mesh => model%mesh)
            allocate (index_of(mesh%nnode))
            allocate (contact%node(0), contact%pair(0), contact%group(0))
            ns = 0
            nm = 0
            do ip = 1, size(model%contact_pairs)
                ns = ns + size(model%surfaces(model%contact_pairs(ip)%slave)%element)
                nm = nm + size(model%surfaces(model%contact_pairs(ip)%master)%element)
            end do
            allocate (contact%seg(2, ns), contact%seg_element(ns))
            allocate (contact%mseg(2, nm), contact%mseg_element(nm), contact%mseg_pair(nm))
            ns = 0
            nm = 0
            do ip = 1, size(model%contact_pairs)
                index_of = 0
                associate (slave => model%surfaces(model%contact_pairs(ip)%slave), &
                           master => model%surfaces(model%contact_pairs(ip)%master))
                    do k = 1, size(slave%element)
                        e = slave%element(k)
                        f = slave%face(k)
                        a = mesh%conn(f, e)
                        b = mesh%conn(mod(f, 4) + 1, e)
                        ns = ns + 1
                        contact%seg(:, ns) = [slave_index(a), slave_index(b)]
                        contact%seg_element(ns) = e
                    end do
                    do k = 1, size(master%element)
                        e = master%element(k)
                        f = master%face(k)
                        nm = nm + 1
                        contact%mseg(:, nm) = [mesh%conn(f, e), mesh%conn(mod(f, 4) + 1, e)]
                        contact%mseg_element(nm) = e
                        contact%mseg_pair(nm) = ip
                    end do
                end associate
            end do
        end associate
        nc = size(contact%node)
        contact%nc = nc
        allocate (contact%placed(nc), source=.false.)
        allocate (contact%status(nc), contact%slip_sign(nc), source=contact_open)
        allocate (contact%p(nc), contact%q(nc), contact%g0(nc), contact%gap(nc), &
                  contact%slip(nc), source=0.0_dp)
        allocate (contact%u(2, model%mesh%nnode), source=0.0_dp)
        allocate (contact%birth(model%mesh%nnode), source=0)
        allocate (contact%supported(nc), source=.false.)
        allocate (contact%normal(2, nc), contact%tangent(2, nc), source=0.0_dp)
        allocate (contact%w(nc), contact%wref(nc), contact%g(nc), source=0.0_dp)
        allocate (contact%cpl_ptr(nc + 1), source=1)
        allocate (contact%cpl_node(0), contact%cpl_a(0))
        allocate (contact%tgroup(nc), source=0)
        allocate (contact%beta(nc), source=1.0_dp)
        allocate (contact%grp_ptr(1), source=1)
        allocate (contact%grp_node(0))
        contact%s = arc_lengths(model, contact)
    contains
        !> The contact node of mesh node `node` in the current pair, made on first sight.
        integer function slave_index(node)
            integer, intent(in) :: node
            if (index_of(node) == 0) then
                contact%node = [contact%node, node]
                contact%pair = [contact%pair, ip]
                contact%group = [contact%group, model%mesh%group(e)]
                index_of(node) = size(contact%node)
            end if
            slave_index = index_of(node)
        end function slave_index
    end subroutine new_contact

    !> Distance of each slave node along its surface: the segments are chained, each chain
    !> measured from its end with the lowest y (then x), chains of a pair one after another.
    function arc_lengths(model, contact) result(s)
        type(model_t), intent(in) :: model
        type(contact_t), intent(in) :: contact
        real(dp), allocatable :: s(:)
        integer, allocatable :: nseg(:), next(:, :)
        logical, allocatable :: done(:)
        integer :: k, c, start, from, prev, seg_next
        real(dp) :: offset
        allocate (s(contact%nc), source=0.0_dp)
        allocate (nseg(contact%nc), source=0)
        allocate (next(2, contact%nc), source=0)
        allocate (done(contact%nc), source=.false.)
        do k = 1, size(contact%seg, 2)
            do c = 1, 2
                nseg(contact%seg(c, k)) = nseg(contact%seg(c, k)) + 1
                if (nseg(contact%seg(c, k)) <= 2) next(nseg(contact%seg(c, k)), &
                                                       contact%seg(c, k)) = k
            end do
        end do
        offset = 0.0_dp
        do
            ! the lowest unvisited chain end (or any unvisited node of a closed loop)
            start = 0
            do c = 1, contact%nc
                if (done(c)) cycle
                if (start == 0) then
                    start = c
                else if (nseg(c) < nseg(start) .or. (nseg(c) == nseg(start) .and. &
                         lower(model%mesh%x(:, contact%node(c)), &
                               model%mesh%x(:, contact%node(start))))) then
                    start = c
                end if
            end do
            if (start == 0) exit
            from = start
            prev = 0
            s(from) = offset
            done(from) = .true.
            do
                seg_next = 0
                do k = 1, 2
                    if (next(k, from) /= 0 .and. next(k, from) /= prev) then
                        c = other_end(next(k, from), from)
                        if (.not. done(c)) then
                            seg_next = next(k, from)
                            exit
                        end if
                    end if
                end do
                if (seg_next == 0) exit
                c = other_end(seg_next, from)
                s(c) = s(from) + norm2(model%mesh%x(:, contact%node(c)) - &
                                       model%mesh%x(:, contact%node(from)))
                done(c) = .true.
                prev = seg_next
                from = c
            end do
            offset = maxval(s, mask=done)
        end do
    contains
        pure logical function lower(xa, xb)
            real(dp), intent(in) :: xa(2), xb(2)
            lower = xa(2) < xb(2) .or. (xa(2) == xb(2) .and. xa(1) < xb(1))
        end function lower
        pure integer function other_end(k, c)
            integer, intent(in) :: k, c
            other_end = merge(contact%seg(2, k), contact%seg(1, k), contact%seg(1, k) == c)
        end function other_end
    end function arc_lengths

    !> The geometry of the coming increment at the current coordinates x + u (Steps 3-4 and 6
    !> of the paper's search): nodal normals, couplings, weighted gaps; nodes placed since the
    !> last call (a cast pair: their gap counts as closed), and the closure tolerance applied to
    !> open nodes as the first guess of the active set. `changed` when the coupling lists (the
    !> sparse pattern) differ from the last call's.
    subroutine contact_geometry(model, active, contact, changed, searched)
        type(model_t), intent(in) :: model
        logical, intent(in) :: active(:)
        type(contact_t), intent(inout) :: contact
        logical, intent(out) :: changed
        logical, intent(out) :: searched   !! the search ran (not so with small slip)
        real(dp), allocatable :: x(:, :), boxes(:, :), ta(:)
        integer, allocatable :: tc(:), tn(:), old_ptr(:), old_node(:), found(:), marker(:), &
                                old_group(:)
        logical, allocatable :: seg_on(:), mseg_on(:), was_placed(:)
        type(bucket_grid_t) :: grid
        real(dp) :: n_seg(2), radius, cell, d(2, 2), m(2, 2), covered, box(4), lmax
        ! RPIM pairs: the active master segments chained, chain_s the arc length of each
        ! chain node (current coordinates), seg_pos the chain position of a segment's start
        integer, allocatable :: chain_node(:), chain_start(:), seg_chain(:), seg_pos(:)
        real(dp), allocatable :: chain_s(:)
        !> (nc) RPIM: the weighted distance from the straight master segments to the curve
        real(dp), allocatable :: g_curve(:)
        integer :: k, c, j, l, kk, km, nt, nfound, stamp, ip
        associate (mesh => model%mesh)
            x = mesh%x + contact%u
            seg_on = active(contact%seg_element)
            mseg_on = active(contact%mseg_element)
            was_placed = contact%placed
            ! Small slip (EFFECTS SLIP SMALL): the geometry of the last search holds until
            ! faces are placed; only the gaps follow the displacements.
            if (.not. model%effects%large_slip .and. allocated(contact%seg_searched)) then
                if (all(seg_on .eqv. contact%seg_searched) .and. &
                    all(mseg_on .eqv. contact%mseg_searched)) then
                    changed = .false.
                    searched = .false.
                    call weighted_gaps()
                    return
                end if
            end if
            contact%seg_searched = seg_on
            contact%mseg_searched = mseg_on
            searched = .true.
            contact%searches = contact%searches + 1
            do k = 1, size(contact%mseg, 2)
                if (.not. mseg_on(k)) cycle
                where (contact%birth(contact%mseg(:, k)) == 0) &
                    contact%birth(contact%mseg(:, k)) = contact%searches
            end do
            call cast_master_offsets(model, contact%node, contact%pair, contact%seg, seg_on, &
                                     contact%mseg, contact%mseg_pair, mseg_on, &
                                     contact%birth == contact%searches, x, contact%u)
            contact%placed = .false.
            contact%normal = 0.0_dp
            contact%wref = 0.0_dp
            lmax = 0.0_dp
            do k = 1, size(contact%seg, 2)
                if (.not. seg_on(k)) cycle
                associate (xa => x(:, contact%node(contact%seg(1, k))), &
                           xb => x(:, contact%node(contact%seg(2, k))))
                    n_seg = face_normal(xa, xb)
                    lmax = max(lmax, norm2(xb - xa))
                    do j = 1, 2
                        c = contact%seg(j, k)
                        contact%placed(c) = .true.
                        contact%normal(:, c) = contact%normal(:, c) + n_seg
                        contact%wref(c) = contact%wref(c) + 0.5_dp*norm2(xb - xa)
                    end do
                end associate
            end do
            do c = 1, contact%nc
                if (contact%placed(c)) contact%normal(:, c) = contact%normal(:, c)/ &
                    max(norm2(contact%normal(:, c)), tiny(1.0_dp))
            end do
            contact%tangent(1, :) = -contact%normal(2, :)
            contact%tangent(2, :) = contact%normal(1, :)
            ! The master segments in a bucket grid.
            allocate (boxes(4, size(contact%mseg, 2)))
            do k = 1, size(contact%mseg, 2)
                associate (xc => x(:, contact%mseg(1, k)), xd => x(:, contact%mseg(2, k)))
                    boxes(:, k) = [min(xc(1), xd(1)), min(xc(2), xd(2)), &
                                   max(xc(1), xd(1)), max(xc(2), xd(2))]
                    if (mseg_on(k)) lmax = max(lmax, norm2(xd - xc))
                end associate
            end do
            cell = max(lmax, tiny(1.0_dp))
            call build_grid(grid, boxes, cell)
            ! Search radius: two of the longest segments (the gap at which a surface is
            ! coupled at all; closer points are resolved by the active set).
            radius = 2.0_dp*lmax
            allocate (marker(size(contact%mseg, 2)), source=0)
            allocate (found(size(contact%mseg, 2)))
            allocate (tc(0), tn(0), ta(0))
            nt = 0
            stamp = 0
            contact%w = 0.0_dp
            allocate (g_curve(contact%nc), source=0.0_dp)
            call chain_master_segments()
            call segment_to_segment()
            call node_to_segment()
            old_ptr = contact%cpl_ptr
            old_node = contact%cpl_node
            call gather_couplings()
            changed = size(old_node) /= size(contact%cpl_node)
            if (.not. changed) changed = any(old_ptr /= contact%cpl_ptr) .or. &
                                         any(old_node /= contact%cpl_node)
            old_group = contact%tgroup
            call friction_groups()
            changed = changed .or. any(old_group /= contact%tgroup)
            contact%g_curve = g_curve
            call weighted_gaps()
        end associate
    contains

        !> Weighted gaps at the start, the supported nodes, the first guess.
        subroutine weighted_gaps()
            integer :: c, kk, ip
            do c = 1, contact%nc
                contact%g(c) = 0.0_dp
                do kk = contact%cpl_ptr(c), contact%cpl_ptr(c + 1) - 1
                    contact%g(c) = contact%g(c) - contact%cpl_a(kk)* &
                                   dot_product(contact%normal(:, c), x(:, contact%cpl_node(kk)))
                end do
                contact%g(c) = contact%g(c) + contact%g_curve(c)
                contact%supported(c) = contact%placed(c) .and. &
                                       contact%w(c) > 1.0e-6_dp*contact%wref(c)
                if (.not. contact%supported(c)) then
                    call open_node(c)
                    cycle
                end if
                ip = contact%pair(c)
                if (.not. was_placed(c)) then
                    contact%g0(c) = 0.0_dp
                    if (model%contact_pairs(ip)%cast) contact%g0(c) = contact%g(c)/contact%w(c)
                    contact%gap(c) = contact%g(c)/contact%w(c) - contact%g0(c)
                end if
                contact%g(c) = contact%g(c) - contact%w(c)*contact%g0(c)
                ! (a gap of round-off size, 1e-10 of the node's length, counts as closed)
                if (contact%status(c) == contact_open .and. contact%g(c)/contact%w(c) <= &
                    model%contact_pairs(ip)%tolerance + 1.0e-10_dp*contact%wref(c)) &
                    contact%status(c) = contact_stick
            end do
        end subroutine weighted_gaps

        subroutine open_node(c)
            integer, intent(in) :: c
            contact%status(c) = contact_open
            contact%slip_sign(c) = 0
            contact%p(c) = 0.0_dp
            contact%q(c) = 0.0_dp
        end subroutine open_node

        subroutine add(c, node, a)
            integer, intent(in) :: c, node
            real(dp), intent(in) :: a
            nt = nt + 1
            if (nt > size(tc)) then
                tc = [tc, [(0, kk = 1, nt + 16)]]
                tn = [tn, [(0, kk = 1, nt + 16)]]
                ta = [ta, [(0.0_dp, kk = 1, nt + 16)]]
            end if
            tc(nt) = c
            tn(nt) = node
            ta(nt) = a
        end subroutine add

        !> Mortar: every active slave segment against the facing master segments near it.
        subroutine segment_to_segment()
            do k = 1, size(contact%seg, 2)
                if (.not. seg_on(k)) cycle
                ip = contact%pair(contact%seg(1, k))
                if (model%contact_pairs(ip)%scheme == scheme_nts) cycle
                associate (xa => x(:, contact%node(contact%seg(1, k))), &
                           xb => x(:, contact%node(contact%seg(2, k))))
                    n_seg = face_normal(xa, xb)
                    box = [min(xa(1), xb(1)) - radius, min(xa(2), xb(2)) - radius, &
                           max(xa(1), xb(1)) + radius, max(xa(2), xb(2)) + radius]
                    stamp = stamp + 1
                    call query_grid(grid, box, stamp, marker, found, nfound)
                    do kk = 1, nfound
                        km = found(kk)
                        if (.not. mseg_on(km)) cycle
                        if (contact%mseg_pair(km) /= contact%pair(contact%seg(1, k))) cycle
                        associate (xc => x(:, contact%mseg(1, km)), &
                                   xd => x(:, contact%mseg(2, km)))
                            ! facing, and within the search radius across
                            if (dot_product(face_normal(xc, xd), n_seg) >= 0.0_dp) cycle
                            if (min(abs(dot_product(xc - xa, n_seg)), &
                                    abs(dot_product(xd - xa, n_seg))) > radius) cycle
                            call mortar_segment_pair(xa, xb, xc, xd, d, m, covered)
                            if (covered > 0.0_dp .and. &
                                model%contact_pairs(ip)%search == search_rpim) &
                                call rpim_gap(k, km, xa, xb)
                        end associate
                        if (covered <= 0.0_dp) cycle
                        do j = 1, 2
                            contact%w(contact%seg(j, k)) = contact%w(contact%seg(j, k)) + &
                                                           sum(d(j, :))
                            do l = 1, 2
                                call add(contact%seg(j, k), contact%node(contact%seg(l, k)), &
                                         d(j, l))
                                call add(contact%seg(j, k), contact%mseg(l, km), -m(j, l))
                            end do
                        end do
                    end do
                end associate
            end do
        end subroutine segment_to_segment

        !> The active master segments of RPIM pairs in chains (each segment's end is the next
        !> one's start: the faces of a surface run with the body on their left, and both
        !> faces' elements are of one group), with the arc length of every chain node.
        subroutine chain_master_segments()
            integer, allocatable :: next_seg(:), starts_at(:)
            logical, allocatable :: has_previous(:)
            integer :: ks, kn, n
            allocate (seg_chain(size(contact%mseg, 2)), seg_pos(size(contact%mseg, 2)), &
                      source=0)
            allocate (chain_node(0), chain_start(1), chain_s(0))
            chain_start(1) = 1
            if (.not. any(model%contact_pairs%search == search_rpim)) return
            allocate (starts_at(size(x, 2)), source=0)
            allocate (has_previous(size(contact%mseg, 2)), source=.false.)
            allocate (next_seg(size(contact%mseg, 2)), source=0)
            do ks = 1, size(contact%mseg, 2)
                if (mseg_on(ks)) starts_at(contact%mseg(1, ks)) = ks
            end do
            do ks = 1, size(contact%mseg, 2)
                if (.not. mseg_on(ks)) cycle
                kn = starts_at(contact%mseg(2, ks))
                if (kn == 0) cycle
                if (contact%mseg_pair(kn) /= contact%mseg_pair(ks)) cycle
                if (.not. (same_birth(ks) .and. same_birth(kn))) cycle
                if (held(ks) .or. held(kn)) cycle
                ! A chain ends where the face passes to elements of another group: a layer
                ! placed at another time, whose displacements since placement (and so the
                ! face's geometry) have a kink there by construction (docs/theory.md s. 14).
                if (model%mesh%group(contact%mseg_element(kn)) /= &
                    model%mesh%group(contact%mseg_element(ks))) cycle
                next_seg(ks) = kn
                has_previous(kn) = .true.
            end do
            do ks = 1, size(contact%mseg, 2)
                if (.not. mseg_on(ks) .or. has_previous(ks) .or. seg_chain(ks) /= 0) cycle
                if (.not. same_birth(ks) .or. held(ks)) cycle
                if (model%contact_pairs(contact%mseg_pair(ks))%search /= search_rpim) cycle
                n = size(chain_start)
                chain_node = [chain_node, contact%mseg(1, ks)]
                chain_s = [chain_s, 0.0_dp]
                kn = ks
                do while (kn /= 0)
                    seg_chain(kn) = n
                    seg_pos(kn) = size(chain_node)
                    chain_node = [chain_node, contact%mseg(2, kn)]
                    chain_s = [chain_s, chain_s(size(chain_s)) + &
                               norm2(x(:, contact%mseg(2, kn)) - x(:, contact%mseg(1, kn)))]
                    kn = next_seg(kn)
                end do
                chain_start = [chain_start, size(chain_node) + 1]
            end do
        end subroutine chain_master_segments

        !> Both nodes of master segment ks were placed at one search. A face placed on an
        !> earlier one starts from its settled nodes to nodes at their design place: the
        !> face's geometry (x + u since placement) bends there by construction, by the
        !> settlement before the placement, however fine the mesh; a smooth curve through
        !> such a bend would be an artefact (docs/theory.md section 14). Such a segment is
        !> left straight.
        pure logical function same_birth(ks)
            integer, intent(in) :: ks
            same_birth = contact%birth(contact%mseg(1, ks)) == contact%birth(contact%mseg(2, ks))
        end function same_birth

        !> A node of master segment ks is pinned by BOUNDARY in both directions (a support:
        !> at the dam's toe, the rock; a roller, such as a plane of symmetry, is not): the
        !> face bends there by the support's reaction, a corner of the displacement field
        !> that no refinement removes (issue 22); a smooth curve through it would spread that
        !> corner over the chain's node spacing. Such a segment is left straight.
        pure logical function held(ks)
            integer, intent(in) :: ks
            held = all(model%fixed(:, contact%mseg(1, ks))) .or. &
                   all(model%fixed(:, contact%mseg(2, ks)))
        end function held

        !> RPIM (paper Step 3): the master surface's geometry is the smooth curve
        !> x(s) = sum phi_i(s) x_i through its nodes; the forces still pass through the
        !> element faces' shape functions (mortar_segment_pair), so that the master receives
        !> tractions consistent with its elements. Here: the weighted distance from the
        !> straight master segment km to the curve, across slave segment k,
        !> g_curve_j += int Phi_j n_j . (x(s*) - x_lin(eta)) ds, s* the curve point straight
        !> across each integration point (Newton on (x(s) - x_p) . t = 0).
        subroutine rpim_gap(k, km, xa, xb)
            integer, intent(in) :: k, km
            real(dp), intent(in) :: xa(2), xb(2)
            real(dp) :: xi(3), w(3), eta(3), t(2), xp(2), sv, f, f1, ds, phi_s(2), h, &
                        x_lin(2), x_curve(2)
            integer :: ig, ch, lo, hi, it, jj
            ch = seg_chain(km)
            if (ch == 0) return
            lo = chain_start(ch)
            hi = chain_start(ch + 1) - 1
            associate (xc => x(:, contact%mseg(1, km)), xd => x(:, contact%mseg(2, km)))
                call mortar_cell_points(xa, xb, xc, xd, xi, w, eta, covered)
                if (covered <= 0.0_dp) return
                t = (xb - xa)/norm2(xb - xa)
                h = chain_s(seg_pos(km) + 1) - chain_s(seg_pos(km))
                do ig = 1, 3
                    xp = 0.5_dp*(1.0_dp - xi(ig))*xa + 0.5_dp*(1.0_dp + xi(ig))*xb
                    x_lin = xc + 0.5_dp*(eta(ig) + 1.0_dp)*(xd - xc)
                    sv = chain_s(seg_pos(km)) + 0.5_dp*(eta(ig) + 1.0_dp)*h
                    do it = 1, 20
                        f = dot_product(rpim_curve(sv, lo, hi) - xp, t)
                        f1 = (dot_product(rpim_curve(sv + 1.0e-6_dp*h, lo, hi) - xp, t) - f)/ &
                             (1.0e-6_dp*h)
                        if (abs(f1) <= tiny(1.0_dp)) exit
                        ds = -f/f1
                        sv = min(max(sv + ds, chain_s(lo)), chain_s(hi))
                        if (abs(ds) <= 1.0e-12_dp*h) exit
                    end do
                    x_curve = rpim_curve(sv, lo, hi)
                    phi_s = dual_shape(xi(ig))
                    do jj = 1, 2
                        g_curve(contact%seg(jj, k)) = g_curve(contact%seg(jj, k)) + &
                            phi_s(jj)*w(ig)*dot_product(contact%normal(:, contact%seg(jj, k)), &
                                                        x_curve - x_lin)
                    end do
                end do
            end associate
        end subroutine rpim_gap

        !> The RPIM curve of the chain nodes lo..hi at arc length s.
        function rpim_curve(s, lo, hi) result(xc)
            real(dp), intent(in) :: s
            integer, intent(in) :: lo, hi
            real(dp) :: xc(2)
            real(dp), allocatable :: ph(:)
            integer :: f0, ns, q
            call rpim_support(chain_s(lo:hi), s, f0, ns)
            allocate (ph(ns))
            call rpim_shape(chain_s(lo + f0 - 1:lo + f0 + ns - 2), s, ph)
            xc = 0.0_dp
            do q = 1, ns
                xc = xc + ph(q)*x(:, chain_node(lo + f0 + q - 2))
            end do
        end function rpim_curve

        !> Node-to-segment: each slave node against the nearest master point straight across
        !> it along its normal, weighted by its tributary length.
        subroutine node_to_segment()
            real(dp) :: lambda
            integer :: best_k
            do c = 1, contact%nc
                if (.not. contact%placed(c)) cycle
                if (model%contact_pairs(contact%pair(c))%scheme /= scheme_nts) cycle
                call nearest_master(c, best_k, lambda)
                if (best_k == 0) cycle
                contact%w(c) = contact%wref(c)
                call add(c, contact%node(c), contact%wref(c))
                call add(c, contact%mseg(1, best_k), -contact%wref(c)*(1.0_dp - lambda))
                call add(c, contact%mseg(2, best_k), -contact%wref(c)*lambda)
            end do
        end subroutine node_to_segment

        !> The active facing master segment of c's pair straight across slave node c along its
        !> normal, the nearest within the search radius (0: none), and where it is hit.
        subroutine nearest_master(c, best_k, best_lambda)
            integer, intent(in) :: c
            integer, intent(out) :: best_k
            real(dp), intent(out) :: best_lambda
            real(dp) :: lambda, distance, best
            logical :: hit
            associate (xs => x(:, contact%node(c)), n => contact%normal(:, c))
                box = [xs(1) - radius, xs(2) - radius, xs(1) + radius, xs(2) + radius]
                stamp = stamp + 1
                call query_grid(grid, box, stamp, marker, found, nfound)
                best = huge(1.0_dp)
                best_k = 0
                best_lambda = 0.0_dp
                do kk = 1, nfound
                    km = found(kk)
                    if (.not. mseg_on(km)) cycle
                    if (contact%mseg_pair(km) /= contact%pair(c)) cycle
                    associate (xc => x(:, contact%mseg(1, km)), &
                               xd => x(:, contact%mseg(2, km)))
                        if (dot_product(face_normal(xc, xd), n) >= 0.0_dp) cycle
                        call project_node(xs, n, xc, xd, lambda, distance, hit)
                    end associate
                    if (.not. hit .or. abs(distance) > radius) cycle
                    if (abs(distance) < best) then
                        best = abs(distance)
                        best_k = km
                        best_lambda = lambda
                    end if
                end do
            end associate
        end subroutine nearest_master

        !> Friction per master segment (docs/theory.md section 14): in a frictional mortar
        !> pair whose mean active slave face is friction_group_ratio times shorter than its
        !> mean active master face, the supported slave nodes straight across one master
        !> segment form a group that shares one tangential traction and one Coulomb law.
        subroutine friction_groups()
            real(dp), allocatable :: ls(:, :), lm(:, :)
            integer, allocatable :: key(:), members(:), next(:)
            real(dp) :: lambda
            integer :: np, best_k, g
            np = size(model%contact_pairs)
            allocate (ls(2, np), lm(2, np), source=0.0_dp)
            do k = 1, size(contact%seg, 2)
                if (.not. seg_on(k)) cycle
                ip = contact%pair(contact%seg(1, k))
                ls(:, ip) = ls(:, ip) + [norm2(x(:, contact%node(contact%seg(2, k))) - &
                                               x(:, contact%node(contact%seg(1, k)))), 1.0_dp]
            end do
            do k = 1, size(contact%mseg, 2)
                if (.not. mseg_on(k)) cycle
                ip = contact%mseg_pair(k)
                lm(:, ip) = lm(:, ip) + [norm2(x(:, contact%mseg(2, k)) - &
                                               x(:, contact%mseg(1, k))), 1.0_dp]
            end do
            allocate (key(contact%nc), source=0)
            allocate (members(size(contact%mseg, 2)), source=0)
            do c = 1, contact%nc
                ip = contact%pair(c)
                if (.not. contact%placed(c) .or. contact%w(c) <= 0.0_dp) cycle
                if (model%contact_pairs(ip)%scheme == scheme_nts .or. &
                    .not. model%contact_pairs(ip)%friction > 0.0_dp) cycle
                if (ls(2, ip) <= 0.0_dp .or. lm(2, ip) <= 0.0_dp) cycle
                if (lm(1, ip)/lm(2, ip) < friction_group_ratio*ls(1, ip)/ls(2, ip)) cycle
                call nearest_master(c, best_k, lambda)
                if (best_k == 0) best_k = closest_master(c)
                if (best_k == 0) cycle
                key(c) = best_k
                members(best_k) = members(best_k) + 1
            end do
            ! groups numbered in the order of their master segments
            contact%ngroup = count(members > 0)
            contact%tgroup = 0
            deallocate (contact%grp_ptr, contact%grp_node)
            allocate (contact%grp_ptr(contact%ngroup + 1), contact%grp_node(count(key > 0)))
            contact%grp_ptr(1) = 1
            g = 0
            do k = 1, size(members)
                if (members(k) == 0) cycle
                g = g + 1
                contact%grp_ptr(g + 1) = contact%grp_ptr(g) + members(k)
                members(k) = g
            end do
            next = contact%grp_ptr(1:contact%ngroup)
            do c = 1, contact%nc
                if (key(c) == 0) cycle
                g = members(key(c))
                contact%tgroup(c) = g
                contact%grp_node(next(g)) = c
                next(g) = next(g) + 1
            end do
        end subroutine friction_groups

        !> The active master segment of c's pair closest to slave node c (a node beyond the
        !> ends of the master surface, straight across none of it), 0 if none in the radius.
        integer function closest_master(c) result(best_k)
            integer, intent(in) :: c
            real(dp) :: lambda, distance, best
            associate (xs => x(:, contact%node(c)))
                box = [xs(1) - radius, xs(2) - radius, xs(1) + radius, xs(2) + radius]
                stamp = stamp + 1
                call query_grid(grid, box, stamp, marker, found, nfound)
                best = radius
                best_k = 0
                do kk = 1, nfound
                    km = found(kk)
                    if (.not. mseg_on(km)) cycle
                    if (contact%mseg_pair(km) /= contact%pair(c)) cycle
                    associate (xc => x(:, contact%mseg(1, km)), xd => x(:, contact%mseg(2, km)))
                        lambda = min(max(dot_product(xs - xc, xd - xc)/ &
                                         max(dot_product(xd - xc, xd - xc), tiny(1.0_dp)), &
                                         0.0_dp), 1.0_dp)
                        distance = norm2(xc + lambda*(xd - xc) - xs)
                    end associate
                    if (distance < best) then
                        best = distance
                        best_k = km
                    end if
                end do
            end associate
        end function closest_master

        !> The triplets (c, node, a) summed into each contact node's coupling list, nodes in
        !> ascending order; w(c) = the sum of its slave coefficients.
        subroutine gather_couplings()
            integer, allocatable :: count(:), order(:), slot(:)
            integer :: t, pos
            allocate (count(contact%nc + 1), source=0)
            do t = 1, nt
                count(tc(t) + 1) = count(tc(t) + 1) + 1
            end do
            count(1) = 1
            do c = 1, contact%nc
                count(c + 1) = count(c + 1) + count(c)
            end do
            allocate (order(nt), slot(contact%nc))
            slot = count(1:contact%nc)
            do t = 1, nt
                order(slot(tc(t))) = t
                slot(tc(t)) = slot(tc(t)) + 1
            end do
            deallocate (contact%cpl_node, contact%cpl_a)
            allocate (contact%cpl_node(nt), contact%cpl_a(nt))
            contact%cpl_ptr(1) = 1
            pos = 0
            do c = 1, contact%nc
                do kk = count(c), count(c + 1) - 1
                    t = order(kk)
                    ! merge with an entry of the same node already in c's list
                    do j = contact%cpl_ptr(c), pos
                        if (contact%cpl_node(j) == tn(t)) exit
                    end do
                    if (j > pos) then
                        pos = pos + 1
                        contact%cpl_node(pos) = tn(t)
                        contact%cpl_a(pos) = 0.0_dp
                        j = pos
                    end if
                    contact%cpl_a(j) = contact%cpl_a(j) + ta(t)
                end do
                call sort_pairs(contact%cpl_node(contact%cpl_ptr(c):pos), &
                                contact%cpl_a(contact%cpl_ptr(c):pos))
                contact%cpl_ptr(c + 1) = pos + 1
            end do
            contact%cpl_node = contact%cpl_node(1:pos)
            contact%cpl_a = contact%cpl_a(1:pos)
        end subroutine gather_couplings
    end subroutine contact_geometry

    !> Sort a short list of nodes ascending, carrying their coefficients.
    pure subroutine sort_pairs(nodes, a)
        integer, intent(inout) :: nodes(:)
        real(dp), intent(inout) :: a(:)
        integer :: i, j, key
        real(dp) :: value
        do i = 2, size(nodes)
            key = nodes(i)
            value = a(i)
            j = i - 1
            do while (j >= 1)
                if (nodes(j) <= key) exit
                nodes(j + 1) = nodes(j)
                a(j + 1) = a(j)
                j = j - 1
            end do
            nodes(j + 1) = key
            a(j + 1) = value
        end do
    end subroutine sort_pairs
end module cfrd_contact
