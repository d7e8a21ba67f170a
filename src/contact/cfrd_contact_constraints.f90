!> The contact elements in the global system (docs/theory.md section 14): for each slave
!> node c of a contact_t (its geometry from cfrd_contact's search), its equation numbers,
!> its matrix rows and right-hand side (the constraint of its status: open, stick or slip),
!> the multipliers unpacked from a solve, the primal-dual active-set update of the statuses,
!> the contact forces on the nodes, and the state accepted with an increment.
module cfrd_contact_constraints
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t
    use cfrd_contact, only: contact_t, contact_open, contact_stick, contact_slip
    implicit none
    private

    public :: contact_element_dofs, contact_element_matrix, contact_rhs, contact_unpack
    public :: contact_update_sets, contact_stick_excess, contact_forces, contact_accept
    public :: contact_group_dofs, contact_group_matrix, contact_shear_shape

contains

    !> Equation numbers of contact element c: its coupled nodes' dofs (eq(2, nnode), 0 when
    !> prescribed) and its multipliers p, q at neq_u + 2c - 1, neq_u + 2c.
    pure function contact_element_dofs(contact, c, eq, neq_u) result(dofs)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: c, eq(:, :), neq_u
        integer, allocatable :: dofs(:)
        integer :: k, m
        m = contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)
        allocate (dofs(2*m + 2))
        do k = 1, m
            dofs(2*k - 1:2*k) = eq(:, contact%cpl_node(contact%cpl_ptr(c) + k - 1))
        end do
        dofs(2*m + 1:2*m + 2) = [neq_u + 2*c - 1, neq_u + 2*c]
    end function contact_element_dofs

    !> The matrix of contact element c for its current status (docs/theory.md section 14):
    !> columns of p and q carry the contact forces, the rows the constraints (closed: zero gap;
    !> stick: zero slip; slip: q = mu p sign; open: p = q = 0). Multipliers are scaled by
    !> `scale` (a stiffness per length) so that all entries are of the size of K's.
    pure subroutine contact_element_matrix(contact, c, mu, scale, constrains, ke, viscous)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: c
        real(dp), intent(in) :: mu, scale
        !> slip rows: q = mu p sign - viscous c_n slip (a regularisation, 0 unless a body held
        !> by friction alone slips everywhere and the matrix is singular)
        real(dp), intent(in) :: viscous
        !> the normal / tangential row reaches a free dof (else it is left out: p or q = 0)
        logical, intent(in) :: constrains(2)
        real(dp), intent(out) :: ke(:, :)
        integer :: k, m, kp, kq
        logical :: regularised
        real(dp) :: a, diag
        logical :: normal_row, tangential_row, grouped
        m = contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)
        kp = 2*m + 1
        kq = 2*m + 2
        ke = 0.0_dp
        diag = row_diagonal(contact, c, scale)
        normal_row = contact%status(c) /= contact_open .and. constrains(1)
        ! a closed node of a friction group: its tangential row is the group's
        ! (contact_group_matrix)
        grouped = contact%tgroup(c) > 0 .and. contact%status(c) /= contact_open .and. &
                  constrains(2)
        tangential_row = contact%status(c) == contact_stick .and. constrains(2) .and. &
                         .not. grouped
        regularised = contact%status(c) == contact_slip .and. constrains(2) .and. &
                      viscous > 0 .and. .not. grouped
        do k = 1, m
            a = scale*contact%cpl_a(contact%cpl_ptr(c) + k - 1)
            ke(2*k - 1:2*k, kp) = a*contact%normal(:, c)
            ke(2*k - 1:2*k, kq) = -a*contact%tangent(:, c)
            if (normal_row) ke(kp, 2*k - 1:2*k) = a*contact%normal(:, c)
            if (tangential_row) ke(kq, 2*k - 1:2*k) = -a*contact%tangent(:, c)
            if (regularised) ke(kq, 2*k - 1:2*k) = viscous*a/contact%w(c)*contact%tangent(:, c)
        end do
        if (.not. normal_row) ke(kp, kp) = diag
        if (.not. tangential_row .and. .not. grouped) then
            ke(kq, kq) = diag
            if (contact%status(c) == contact_slip .and. constrains(2)) &
                ke(kq, kp) = -mu*contact%slip_sign(c)*diag
        end if
    end subroutine contact_element_matrix

    !> The size of a multiplier row's diagonal: K's size. An open row (p or q = 0) of a node
    !> not placed yet has no length of its own, and a row of tiny size would read as singular
    !> to a solver that does not scale rows (cfrd_umfpack: set_row_scaling).
    pure real(dp) function row_diagonal(contact, c, scale) result(diag)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: c
        real(dp), intent(in) :: scale
        real(dp) :: length
        length = contact%wref(c)
        if (.not. length > 0.0_dp) length = maxval(contact%wref)
        if (.not. length > 0.0_dp) length = 1.0_dp
        diag = scale*length
    end function row_diagonal

    !> Each friction group's shear shape beta (contact_t) from its members' pressures, those
    !> of the accepted state at the start of an increment (docs/theory.md section 14).
    pure subroutine contact_shear_shape(contact)
        type(contact_t), intent(inout) :: contact
        real(dp) :: pmax
        integer :: g
        contact%beta = 1.0_dp
        do g = 1, contact%ngroup
            associate (members => contact%grp_node(contact%grp_ptr(g):contact%grp_ptr(g + 1) - 1))
                pmax = maxval(max(contact%p(members), 0.0_dp))
                if (pmax > 0.0_dp) contact%beta(members) = max(contact%p(members), 0.0_dp)/pmax
            end associate
        end do
    end subroutine contact_shear_shape

    !> Equation numbers of friction group g: its members' contact element dofs one after
    !> another (contact_element_dofs).
    pure function contact_group_dofs(contact, g, eq, neq_u) result(dofs)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: g, eq(:, :), neq_u
        integer, allocatable :: dofs(:)
        integer :: i
        allocate (dofs(0))
        do i = contact%grp_ptr(g), contact%grp_ptr(g + 1) - 1
            dofs = [dofs, contact_element_dofs(contact, contact%grp_node(i), eq, neq_u)]
        end do
    end function contact_group_dofs

    !> The members of friction group g whose tangential rows are the group's (closed, the
    !> row constraining): `on`; the first of them with a shear share, `rep` (0: none); the
    !> shares beta_c / beta_rep of the members (0 unless on), and sum_c w_c beta_c / beta_rep.
    pure subroutine group_members(contact, g, constrains, members, on, rep, share, total)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: g
        logical, intent(in) :: constrains(:, :)
        integer, allocatable, intent(out) :: members(:)
        logical, allocatable, intent(out) :: on(:)
        integer, intent(out) :: rep
        real(dp), allocatable, intent(out) :: share(:)
        real(dp), intent(out) :: total
        members = contact%grp_node(contact%grp_ptr(g):contact%grp_ptr(g + 1) - 1)
        on = contact%status(members) /= contact_open .and. constrains(2, members)
        rep = findloc(on .and. contact%beta(members) > 0.0_dp, .true., dim=1)
        allocate (share(size(members)), source=0.0_dp)
        total = 0.0_dp
        if (rep == 0) return
        where (on) share = contact%beta(members)/contact%beta(members(rep))
        total = sum(contact%w(members)*share)
    end subroutine group_members

    !> The tangential rows of friction group g (docs/theory.md section 14): one shear
    !> traction q_c = beta_c q_G for its closed members (q_c - (beta_c / beta_r) q_r = 0, r
    !> the first of them with beta > 0) and one Coulomb law, in the row of q_r: stick,
    !> sum_c beta_c s_c(du) = 0; slip, the shear force sum_c w_c q_c = mu sign sum_c w_c p_c.
    !> Local dofs: the members' element dofs in turn.
    pure subroutine contact_group_matrix(contact, g, mu, scale, constrains, ke, viscous)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: g
        real(dp), intent(in) :: mu, scale, viscous
        logical, intent(in) :: constrains(:, :)
        real(dp), intent(out) :: ke(:, :)
        integer, allocatable :: members(:), offset(:)
        logical, allocatable :: on(:)
        real(dp), allocatable :: share(:)
        integer :: i, k, c, r, m, rq, cq
        real(dp) :: total, a, diag_r
        ke = 0.0_dp
        call group_members(contact, g, constrains, members, on, r, share, total)
        allocate (offset(size(members) + 1))
        offset(1) = 0
        do i = 1, size(members)
            c = members(i)
            offset(i + 1) = offset(i) + 2*(contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)) + 2
        end do
        do i = 1, size(members)
            ! closed members without a shear share: q_c = 0
            if (on(i) .and. (r == 0 .or. i /= r)) then
                c = members(i)
                ke(offset(i + 1), offset(i + 1)) = row_diagonal(contact, c, scale)
                if (r > 0) ke(offset(i + 1), offset(r + 1)) = -share(i)* &
                                                               row_diagonal(contact, c, scale)
            end if
        end do
        if (r == 0) return
        rq = offset(r + 1)
        diag_r = row_diagonal(contact, members(r), scale)
        if (contact%status(members(r)) == contact_slip) ke(rq, rq) = diag_r
        do i = 1, size(members)
            if (.not. on(i)) cycle
            c = members(i)
            cq = offset(i + 1)
            if (contact%status(members(r)) == contact_slip) &
                ke(rq, cq - 1) = -mu*contact%slip_sign(members(r))*diag_r*contact%w(c)/total
            m = contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)
            do k = 1, m
                a = scale*contact%cpl_a(contact%cpl_ptr(c) + k - 1)*share(i)
                if (contact%status(members(r)) == contact_stick) then
                    ke(rq, offset(i) + 2*k - 1:offset(i) + 2*k) = -a*contact%tangent(:, c)
                else if (viscous > 0.0_dp) then
                    ke(rq, offset(i) + 2*k - 1:offset(i) + 2*k) = viscous*a/total* &
                                                                  contact%tangent(:, c)
                end if
            end do
        end do
    end subroutine contact_group_matrix

    !> Right-hand sides of contact element c's two rows, with the displacement increment
    !> `known` (2, nnode) already taken (earlier corrections, prescribed values).
    pure function contact_rhs(contact, c, scale, known, viscous, constrains) result(b)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: c
        real(dp), intent(in) :: scale, known(:, :), viscous
        !> (2, nc) the rows that constrain free dofs (the others are p or q = 0)
        logical, intent(in) :: constrains(:, :)
        real(dp) :: b(2), v(2), total
        integer, allocatable :: members(:)
        logical, allocatable :: on(:)
        real(dp), allocatable :: share(:)
        integer :: i, r
        b = 0.0_dp
        if (contact%status(c) == contact_open) return
        v = weighted_motion(contact, c, known)
        if (constrains(1, c)) b(1) = scale*(contact%g(c) - dot_product(contact%normal(:, c), v))
        if (.not. constrains(2, c)) return
        if (contact%tgroup(c) > 0) then
            ! a friction group's row: its first closed member's (contact_group_matrix)
            call group_members(contact, contact%tgroup(c), constrains, members, on, r, &
                               share, total)
            if (r == 0) return
            if (members(r) /= c) return
            v = 0.0_dp
            do i = 1, size(members)
                if (on(i)) v(1) = v(1) + share(i)*dot_product(contact%tangent(:, members(i)), &
                                                   weighted_motion(contact, members(i), known))
            end do
            if (contact%status(c) == contact_stick) b(2) = scale*v(1)
            if (contact%status(c) == contact_slip) b(2) = -viscous*scale/total*v(1)
            return
        end if
        if (contact%status(c) == contact_stick) b(2) = scale*dot_product(contact%tangent(:, c), v)
        if (contact%status(c) == contact_slip) &
            b(2) = -viscous*scale/contact%w(c)*dot_product(contact%tangent(:, c), v)
    end function contact_rhs

    !> sum_i a_ci v_i: the slave side's motion relative to the master side, weighted.
    pure function weighted_motion(contact, c, v) result(r)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: c
        real(dp), intent(in) :: v(:, :)
        real(dp) :: r(2)
        integer :: k
        r = 0.0_dp
        do k = contact%cpl_ptr(c), contact%cpl_ptr(c + 1) - 1
            r = r + contact%cpl_a(k)*v(:, contact%cpl_node(k))
        end do
    end function weighted_motion

    !> Tractions from the solved (scaled) multipliers x(2*nc).
    pure subroutine contact_unpack(contact, x, scale)
        type(contact_t), intent(inout) :: contact
        real(dp), intent(in) :: x(:), scale
        contact%p = scale*x(1:2*contact%nc - 1:2)
        contact%q = scale*x(2:2*contact%nc:2)
        where (contact%status == contact_open)
            contact%p = 0.0_dp
            contact%q = 0.0_dp
        end where
    end subroutine contact_unpack

    !> The primal-dual active-set step after a solve with the increment du (2, nnode)
    !> (Hueber & Wohlmuth 2005), normal and tangential together: closed where
    !> p - c_n gap > 0; a closed node sticks where |q - c_t slip| <= mu p, else slips in the
    !> direction of that trial traction (a slip that turns round goes to stick first).
    !> `changed` when any node's status or slip direction changed. (Holding every closed
    !> node in stick while the normal set changes was tried: it cycles when a prescribed
    !> motion drags a body.)
    pure subroutine contact_update_sets(model, contact, du, scale, changed, one_at_a_time, &
                                       held)
        type(model_t), intent(in) :: model
        type(contact_t), intent(inout) :: contact
        real(dp), intent(in) :: du(:, :), scale
        logical, intent(out) :: changed
        !> change only the node that violates its conditions most (after a cycle)
        logical, intent(in) :: one_at_a_time
        !> (nc) nodes held closed in stick whatever their conditions say (chatter, cycles:
        !> docs/theory.md section 14); their violation is checked by the caller
        logical, intent(in), optional :: held(:)
        real(dp) :: v(2), gap, slip, cn, trial, bound, mu, ptol, violation(contact%nc)
        integer :: c, g, status(contact%nc), sign_new(contact%nc), worst
        logical :: closed(contact%nc), hold(contact%nc)
        ptol = 1.0e-10_dp*max(maxval(abs(contact%p)), tiny(1.0_dp))
        closed = .false.
        violation = 0.0_dp
        do c = 1, contact%nc
            if (.not. contact%supported(c)) cycle
            v = weighted_motion(contact, c, du)
            gap = (contact%g(c) - dot_product(contact%normal(:, c), v))/contact%w(c)
            cn = scale/max(contact%wref(c), tiny(1.0_dp))
            ! a gap below 1e-10 of the node's length counts as closed (round-off)
            closed(c) = contact%p(c) - cn*(gap - 1.0e-10_dp*contact%wref(c)) > 0.0_dp
            violation(c) = abs(contact%p(c) - cn*gap)
        end do
        status = contact_open
        sign_new = 0
        do c = 1, contact%nc
            if (.not. closed(c)) cycle
            v = weighted_motion(contact, c, du)
            slip = dot_product(contact%tangent(:, c), v)/contact%w(c)
            cn = scale/max(contact%wref(c), tiny(1.0_dp))
            mu = model%contact_pairs(contact%pair(c))%friction
            trial = contact%q(c) - cn*slip
            bound = mu*max(contact%p(c), 0.0_dp)
            violation(c) = abs(abs(trial) - bound)
            if (mu > 0.0_dp .and. abs(trial) <= bound*(1.0_dp + 1.0e-9_dp) + ptol) then
                status(c) = contact_stick
            else
                status(c) = contact_slip
                if (mu > 0.0_dp) sign_new(c) = int(sign(1.0_dp, trial))
                ! A slip that turns round passes through stick: try that first (slip
                ! reversal is how the iterates of a sliding-everywhere body chatter).
                if (contact%status(c) == contact_slip .and. &
                    sign_new(c) == -contact%slip_sign(c) .and. sign_new(c) /= 0) then
                    status(c) = contact_stick
                    sign_new(c) = 0
                end if
            end if
        end do
        do g = 1, contact%ngroup
            call group_law(g, status, sign_new, violation)
        end do
        hold = .false.
        if (present(held)) hold = held .and. contact%supported
        if (present(held)) then
            where (held .and. contact%supported)
                status = contact_stick
                sign_new = 0
                violation = -1.0_dp
            end where
            ! a group with a held member sticks as a whole
            do c = 1, contact%nc
                if (contact%tgroup(c) == 0 .or. .not. (held(c) .and. closed(c))) cycle
                where (contact%tgroup == contact%tgroup(c) .and. closed)
                    status = contact_stick
                    sign_new = 0
                end where
            end do
        end if
        if (one_at_a_time) then
            where (status == contact%status .and. sign_new == contact%slip_sign) violation = -1.0_dp
            worst = maxloc(violation, dim=1)
            if (violation(worst) >= 0.0_dp) then
                ! (the worst node's friction group changes with it, and held nodes are
                ! held whatever their status before)
                where ([(c /= worst .and. (contact%tgroup(c) == 0 .or. &
                         contact%tgroup(c) /= contact%tgroup(worst)), c=1, contact%nc)] &
                       .and. .not. hold)
                    status = contact%status
                    sign_new = contact%slip_sign
                end where
            end if
        end if
        changed = any(status /= contact%status) .or. any(sign_new /= contact%slip_sign)
        contact%status = status
        contact%slip_sign = sign_new
    contains
        !> Friction group g (docs/theory.md section 14): its closed members stick or slip
        !> together, by the group's trial traction, its shear force over W less c_n times
        !> the slip of its shear shape, against mu times its normal force over W (W the
        !> closed members' weight; force and slip of the last solve's closed members).
        pure subroutine group_law(g, status, sign_new, violation)
            integer, intent(in) :: g
            integer, intent(inout) :: status(:), sign_new(:)
            real(dp), intent(inout) :: violation(:)
            integer, allocatable :: members(:)
            logical, allocatable :: on(:), before(:)
            real(dp) :: total, f_g, s_g, n_g, cn_g, mu, trial, bound
            integer :: i, first, previous, sign_g
            members = contact%grp_node(contact%grp_ptr(g):contact%grp_ptr(g + 1) - 1)
            on = closed(members)
            if (.not. any(on)) return
            ! the shear force and the slip of the shear shape of the last solve, over the
            ! members closed in it (in stick, sum_c beta_c s_c = 0)
            before = contact%status(members) /= contact_open
            if (.not. any(before)) before = on
            f_g = sum(contact%w(members)*contact%q(members), mask=before)
            s_g = 0.0_dp
            do i = 1, size(members)
                if (before(i)) s_g = s_g + contact%beta(members(i))* &
                                     dot_product(contact%tangent(:, members(i)), &
                                                 weighted_motion(contact, members(i), du))
            end do
            total = sum(contact%w(members)*contact%beta(members), mask=before)
            if (total > 0.0_dp) s_g = s_g/total
            total = sum(contact%w(members), mask=on)
            n_g = sum(contact%w(members)*max(contact%p(members), 0.0_dp), mask=on)
            cn_g = scale*count(on)/sum(contact%wref(members), mask=on)
            mu = model%contact_pairs(contact%pair(members(1)))%friction
            ! (a trial traction and its bound, in kPa over the closed members)
            trial = f_g/total - cn_g*s_g
            bound = mu*n_g/total
            first = findloc(before, .true., dim=1)
            previous = contact%status(members(first))
            sign_g = 0
            if (abs(trial) <= bound*(1.0_dp + 1.0e-9_dp) + ptol) then
                status(members) = merge(contact_stick, contact_open, on)
            else
                sign_g = int(sign(1.0_dp, trial))
                ! a slip that turns round passes through stick
                if (previous == contact_slip .and. &
                    sign_g == -contact%slip_sign(members(first))) sign_g = 0
                status(members) = merge(merge(contact_slip, contact_stick, sign_g /= 0), &
                                        contact_open, on)
            end if
            sign_new(members) = merge(sign_g, 0, on)
            where (on) violation(members) = abs(abs(trial) - bound)
        end subroutine group_law
    end subroutine contact_update_sets

    !> How far the tractions of a node in stick break its conditions (kPa): the tension
    !> max(0, -p) plus the friction beyond the cone max(0, |q| - mu p); 0 when they hold.
    pure real(dp) function contact_stick_excess(model, contact, c) result(excess)
        type(model_t), intent(in) :: model
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: c
        real(dp) :: mu, p
        integer, allocatable :: members(:)
        logical, allocatable :: on(:)
        mu = model%contact_pairs(contact%pair(c))%friction
        p = max(contact%p(c), 0.0_dp)
        if (contact%tgroup(c) > 0) then
            ! a friction group's cone: its shear force against mu times its normal force,
            ! over its closed members' weight
            members = contact%grp_node(contact%grp_ptr(contact%tgroup(c)): &
                                       contact%grp_ptr(contact%tgroup(c) + 1) - 1)
            on = contact%status(members) /= contact_open
            if (any(on)) then
                excess = max(0.0_dp, -contact%p(c)) + max(0.0_dp, (abs(sum(contact%w(members)* &
                         contact%q(members), mask=on)) - mu*sum(contact%w(members)* &
                         max(contact%p(members), 0.0_dp), mask=on))/sum(contact%w(members), &
                         mask=on))
                return
            end if
        end if
        excess = max(0.0_dp, -contact%p(c)) + max(0.0_dp, abs(contact%q(c)) - mu*p)
    end function contact_stick_excess

    !> The forces the contact tractions apply to the nodes (2, nnode), kN/m.
    pure subroutine contact_forces(contact, force)
        type(contact_t), intent(in) :: contact
        real(dp), intent(inout) :: force(:, :)
        integer :: c, k
        force = 0.0_dp
        do c = 1, contact%nc
            if (contact%status(c) == contact_open) cycle
            do k = contact%cpl_ptr(c), contact%cpl_ptr(c + 1) - 1
                force(:, contact%cpl_node(k)) = force(:, contact%cpl_node(k)) - &
                    contact%cpl_a(k)*(contact%p(c)*contact%normal(:, c) - &
                                      contact%q(c)*contact%tangent(:, c))
            end do
        end do
    end subroutine contact_forces

    !> After an accepted increment du: displacements since placement, gaps and slips.
    pure subroutine contact_accept(contact, du)
        type(contact_t), intent(inout) :: contact
        real(dp), intent(in) :: du(:, :)
        real(dp) :: v(2)
        integer :: c
        do c = 1, contact%nc
            if (.not. contact%supported(c)) cycle
            v = weighted_motion(contact, c, du)
            contact%gap(c) = (contact%g(c) - dot_product(contact%normal(:, c), v))/contact%w(c)
            contact%slip(c) = contact%slip(c) + dot_product(contact%tangent(:, c), v)/contact%w(c)
        end do
        contact%u = contact%u + du
    end subroutine contact_accept
end module cfrd_contact_constraints
