!> The linear-algebra objects of one active set of elements (and contact pairs): the
!> equation numbering, the sparse pattern, the tangent's values and UMFPACK's factors,
!> with the symbolic factorisation kept while the pattern holds (docs/theory.md section 9).
!> With contact, the multiplier rows of the current active set are added to K before each
!> factorisation, or the factors updated for the rows that changed (section 14).
module cfrd_linear_system
    use, intrinsic :: iso_c_binding, only: c_funptr, c_funloc, c_int
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_clock, only: wall_seconds
    use cfrd_strings, only: to_text
    use cfrd_model, only: model_t
    use cfrd_material_law, only: all_linear
    use cfrd_results, only: stage_result_t
    use cfrd_sparse, only: sparse_pattern_t, build_pattern, assemble_element
    use cfrd_linear_solver, only: linear_solver_t
    use cfrd_matrix_market, only: write_matrix_if_asked
    use cfrd_assembly, only: element_box_t, dof_map_t, number_equations, force_memo_t
    use cfrd_contact, only: contact_t, contact_slip, contact_stick
    use cfrd_contact_constraints, only: contact_element_dofs, contact_element_matrix, &
                                        contact_group_dofs, contact_group_matrix
    implicit none
    private

    public :: system_t, new_system, factorise_values, factorise_contact, multiplier_scale
    public :: slip_viscosity, expect_next, forget_ahead, ahead_thread


    !> The linear-algebra objects of one active set.
    type :: system_t
        type(dof_map_t) :: dofmap
        type(sparse_pattern_t) :: pattern
        type(linear_solver_t) :: solver    !! CHOLMOD or UMFPACK (cfrd_linear_solver)
        real(dp), allocatable :: values(:)
        logical :: factorised_linear = .false.   !! a constant tangent is factorised already
        !> With contact: the tangent K alone (the contact rows are added per active set),
        !> and the scale of the multipliers (a stiffness per length, docs/theory.md s. 14)
        real(dp), allocatable :: k_values(:)
        real(dp) :: contact_scale = 1.0_dp
        !> contact_scale is given (a restart: the scale of the system the stored run had in
        !> use), not to be computed at the first assembly of this system
        logical :: scale_given = .false.
        !> (2, ncontact) the normal / tangential constraint of a slave node moves some free
        !> dof (else every dof it ties is prescribed: the constraint is left out)
        logical, allocatable :: constrains(:, :)
        !> Regularisation of the slip rows for this solve (contact_element_matrix): 0, or
        !> slip_viscosity after a singular factorisation with sliding nodes
        real(dp) :: viscous = 0.0_dp
        !> The solver keeps the factorisation of the tangent at the start state of a
        !> rejected midpoint increment (linear_solver_t%keep): its retry from the same state
        !> takes it back instead of factorising the same matrix again (issue 21)
        logical :: start_kept = .false.
        !> The internal forces of the last accepted stresses (cfrd_assembly: force_memo_t)
        type(force_memo_t) :: forces
        !> the pattern's symbolic analysis was prepared ahead (new_system), not yet counted
        logical :: prepared_ahead = .false.
    end type system_t

    !> The slip rows' regularisation when a body held by friction alone slips at every
    !> node (a mechanism of the linearised equations): q = mu p sign - 1e-9 c_n slip.
    real(dp), parameter :: slip_viscosity = 1.0e-9_dp
    !> From this many equations on, UMFPACK orders a contact system by METIS instead of AMD:
    !> at x4 (20,818) and x8 (82,594) its numeric factorisations save more than its dearer
    !> analyses cost, at x2 (5,000) they do not [choice, measured: docs/performance.md (ab)].
    integer, parameter :: contact_metis_min = 10000

    !> The next FILL stage's system prepared ahead, on a second thread (cfrd_behind.c's
    !> queue ahead), while the current stage is solved (docs/performance.md (ak)): its
    !> equations, pattern and symbolic analysis, taken by new_system when the active set and
    !> the contact couplings are those it was prepared for. One run at a time per process.
    logical, allocatable, save :: next_active(:)    !! the next FILL stage's (expect_next)
    !> the preparation's inputs (read by the job between its post and c_ahead_wait)
    type(model_t), pointer, save :: ahead_model => null()
    type(element_box_t), pointer, save :: ahead_library(:) => null()
    logical, allocatable, save :: ahead_active(:)
    type(contact_t), save :: ahead_contact           !! its coupling lists only
    logical, save :: ahead_has_contact = .false.
    !> a job posted (its result not yet taken); the job's result and success
    logical, save :: ahead_posted = .false.
    type(system_t), save :: ahead
    logical, save :: ahead_ok = .false.
    !> a preparation scheduled by new_system, posted after the system's own analysis
    logical, save :: pending = .false.
    type(model_t), pointer, save :: pending_model => null()
    type(element_box_t), pointer, save :: pending_library(:) => null()
    type(contact_t), save :: pending_contact         !! its coupling lists only
    logical, save :: pending_has_contact = .false.

    interface
        integer(c_int) function c_ahead_post(job) bind(C, name='cfrd_ahead_post')
            import :: c_funptr, c_int
            type(c_funptr), value :: job
        end function c_ahead_post
        subroutine c_ahead_wait() bind(C, name='cfrd_ahead_wait')
        end subroutine c_ahead_wait
        integer(c_int) function c_ahead_thread() bind(C, name='cfrd_ahead_thread')
            import :: c_int
        end function c_ahead_thread
    end interface

contains

    !> Equations, pattern and a fresh solver for the current active set.
    !> With contact, each slave node is one more element (its coupled nodes and its two
    !> multiplier equations, numbered after the displacement equations).
    !> The equations, pattern and symbolic analysis of this active set are taken from the
    !> system prepared ahead when it was prepared for the same active set and couplings
    !> (expect_next): the same numbers, bit for bit. Then the next FILL stage's system is
    !> prepared ahead, on a second thread, while this one is solved.
    subroutine new_system(model, library, active, system, error, contact, has_contact)
        type(model_t), target, intent(in) :: model
        type(element_box_t), target, intent(in) :: library(:)
        logical, intent(in) :: active(:)
        type(system_t), intent(inout) :: system
        type(error_t), allocatable, intent(out) :: error
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: has_contact
        logical :: taken
        call system%solver%release()
        call system%solver%configure(model%linear_solver, .not. has_contact, &
                                     all_linear(model, active), &
                                     multipliers=merge(2*contact%nc, 0, has_contact))
        taken = take_ahead(active, contact, has_contact, system)
        system%prepared_ahead = taken
        if (.not. taken) then
            call build_structure(model, library, active, system, error, contact, has_contact)
            if (allocated(error)) return
        end if
        if (has_contact) then
            system%constrains = constraining_rows(contact, system%dofmap%eq)
            ! The multipliers are scaled to K's size (multiplier_scale): UMFPACK's row
            ! scaling would only push its pivots off the diagonal.
            call system%solver%set_row_scaling(.false.)
            ! METIS on the larger systems; no iterative refinement of the solves of the
            ! factorised matrix: the updated solves refine against the matrix they solve
            ! (docs/theory.md section 6, docs/performance.md (ab)).
            call system%solver%set_metis(system%pattern%n >= contact_metis_min)
            call system%solver%set_refinement(.false.)
        end if
        if (allocated(system%k_values)) deallocate (system%k_values)
        if (allocated(system%values)) deallocate (system%values)
        allocate (system%values(system%pattern%nnz), source=0.0_dp)
        system%factorised_linear = .false.
        system%scale_given = .false.
        system%start_kept = .false.
        ! The next system is prepared ahead now when this one's analysis is at hand, else
        ! after this one's own analysis (factorise_values): two analyses at once would
        ! share METIS's random numbers (a global state), and so their orderings.
        call schedule_ahead(model, library, active, contact, has_contact)
        if (taken) call post_ahead()
    end subroutine new_system

    !> The equations and the sparse pattern of an active set (with contact, of its couplings).
    subroutine build_structure(model, library, active, system, error, contact, has_contact)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        type(system_t), intent(inout) :: system
        type(error_t), allocatable, intent(out) :: error
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: has_contact
        integer, allocatable :: dof_ptr(:), dofs(:), more(:)
        integer :: c, g, k, nelem, pos
        call number_equations(model, library, active, system%dofmap)
        if (has_contact) then
            nelem = model%mesh%nelem
            ! (then each friction group: its members' dofs, docs/theory.md section 14)
            allocate (dof_ptr(nelem + contact%nc + contact%ngroup + 1))
            dof_ptr(1:nelem + 1) = system%dofmap%dof_ptr
            do c = 1, contact%nc
                dof_ptr(nelem + c + 1) = dof_ptr(nelem + c) + 2* &
                    (contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)) + 2
            end do
            do g = 1, contact%ngroup
                dof_ptr(nelem + contact%nc + g + 1) = dof_ptr(nelem + contact%nc + g) + &
                    sum([(dof_ptr(nelem + contact%grp_node(k) + 1) - &
                          dof_ptr(nelem + contact%grp_node(k)), &
                          k=contact%grp_ptr(g), contact%grp_ptr(g + 1) - 1)])
            end do
            allocate (dofs(dof_ptr(size(dof_ptr)) - 1))
            dofs(1:size(system%dofmap%dofs)) = system%dofmap%dofs
            pos = dof_ptr(nelem + 1)
            do c = 1, contact%nc + contact%ngroup
                if (c <= contact%nc) then
                    more = contact_element_dofs(contact, c, system%dofmap%eq, system%dofmap%neq)
                else
                    more = contact_group_dofs(contact, c - contact%nc, system%dofmap%eq, &
                                              system%dofmap%neq)
                end if
                dofs(pos:pos + size(more) - 1) = more
                pos = pos + size(more)
            end do
            call build_pattern(system%pattern, system%dofmap%neq + 2*contact%nc, dof_ptr, &
                               dofs, error)
        else
            call build_pattern(system%pattern, system%dofmap%neq, system%dofmap%dof_ptr, &
                               system%dofmap%dofs, error)
        end if
    end subroutine build_structure

    !> The active set of the next FILL stage (unallocated: none): its system is prepared
    !> ahead from the next new_system on (the stage driver tells it at each stage).
    subroutine expect_next(active)
        logical, allocatable, intent(in) :: active(:)
        if (allocated(next_active)) deallocate (next_active)
        if (allocated(active)) next_active = active
    end subroutine expect_next

    !> Systems are prepared ahead on a thread of their own (false where cfrd_behind.c's queue
    !> ahead has none: one processor, CFRD_AHEAD=0; or before the first preparation posted).
    logical function ahead_thread()
        ahead_thread = c_ahead_thread() == 1
    end function ahead_thread

    !> Nothing prepared or expected any more (the end of a run): the job ahead finished and
    !> its system freed.
    subroutine forget_ahead()
        if (ahead_posted) call c_ahead_wait()
        ahead_posted = .false.
        pending = .false.
        ! a system prepared and not taken: nothing of it kept to the next run
        call ahead%solver%release()
        ahead%dofmap = dof_map_t()
        ahead%pattern = sparse_pattern_t()
        if (allocated(next_active)) deallocate (next_active)
        ahead_model => null()
        ahead_library => null()
        pending_model => null()
        pending_library => null()
    end subroutine forget_ahead

    !> What the next preparation needs from the system just made (of `active`): the model
    !> and library, and the couplings of its contact (their lists, which the pattern is made
    !> of). Nothing when no FILL stage follows, or it activates nothing new.
    subroutine schedule_ahead(model, library, active, contact, has_contact)
        type(model_t), target, intent(in) :: model
        type(element_box_t), target, intent(in) :: library(:)
        logical, intent(in) :: active(:)
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: has_contact
        pending = .false.
        if (.not. allocated(next_active)) return
        if (size(next_active) == size(active)) then
            if (all(next_active .eqv. active)) return
        end if
        pending_model => model
        pending_library => library
        pending_has_contact = has_contact
        call copy_couplings(contact, pending_contact)
        pending = .true.
    end subroutine schedule_ahead

    !> Post the preparation scheduled, unless the one posted last is for the same active set
    !> and couplings (its result still to be taken).
    subroutine post_ahead()
        if (.not. pending) return
        pending = .false.
        if (ahead_posted) then
            if (same_key(next_active, pending_contact, pending_has_contact)) return
            call c_ahead_wait()
            ahead_posted = .false.
        end if
        ahead_model => pending_model
        ahead_library => pending_library
        ahead_active = next_active
        ahead_has_contact = pending_has_contact
        call copy_couplings(pending_contact, ahead_contact)
        ahead_ok = .false.
        ahead_posted = c_ahead_post(c_funloc(prepare_ahead)) /= 0
    end subroutine post_ahead

    !> The job ahead (on the second thread): the system of ahead_active, configured as
    !> new_system configures it, its equations, pattern and symbolic analysis.
    subroutine prepare_ahead() bind(C)
        type(error_t), allocatable :: error
        call ahead%solver%release()
        call ahead%solver%configure(ahead_model%linear_solver, .not. ahead_has_contact, &
                                    all_linear(ahead_model, ahead_active), &
                                    multipliers=merge(2*ahead_contact%nc, 0, &
                                                      ahead_has_contact))
        call build_structure(ahead_model, ahead_library, ahead_active, ahead, error, &
                             ahead_contact, ahead_has_contact)
        if (allocated(error)) return
        call ahead%solver%prepare(ahead%pattern, error)
        ahead_ok = .not. allocated(error)
    end subroutine prepare_ahead

    !> The system prepared ahead for this active set and couplings, moved into `system`
    !> (released and configured): true when there was one.
    logical function take_ahead(active, contact, has_contact, system) result(taken)
        logical, intent(in) :: active(:)
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: has_contact
        type(system_t), intent(inout) :: system
        taken = .false.
        if (.not. ahead_posted) return
        if (.not. same_key(active, contact, has_contact)) return
        call c_ahead_wait()
        ahead_posted = .false.
        if (.not. ahead_ok) return
        system%dofmap%neq = ahead%dofmap%neq
        call move_alloc(ahead%dofmap%eq, system%dofmap%eq)
        call move_alloc(ahead%dofmap%dof_ptr, system%dofmap%dof_ptr)
        call move_alloc(ahead%dofmap%dofs, system%dofmap%dofs)
        system%pattern%n = ahead%pattern%n
        system%pattern%nnz = ahead%pattern%nnz
        call move_alloc(ahead%pattern%colptr, system%pattern%colptr)
        call move_alloc(ahead%pattern%rowind, system%pattern%rowind)
        call move_alloc(ahead%pattern%map_ptr, system%pattern%map_ptr)
        call move_alloc(ahead%pattern%map, system%pattern%map)
        call system%solver%adopt(ahead%solver)
        taken = .true.
    end function take_ahead

    !> The preparation posted is for this active set and these couplings.
    logical function same_key(active, contact, has_contact) result(same)
        logical, intent(in) :: active(:)
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: has_contact
        same = .false.
        if (size(active) /= size(ahead_active)) return
        if (has_contact .neqv. ahead_has_contact) return
        if (.not. all(active .eqv. ahead_active)) return
        if (has_contact) then
            if (contact%nc /= ahead_contact%nc .or. contact%ngroup /= ahead_contact%ngroup) &
                return
            if (.not. (same_list(contact%cpl_ptr, ahead_contact%cpl_ptr) .and. &
                       same_list(contact%cpl_node, ahead_contact%cpl_node) .and. &
                       same_list(contact%grp_ptr, ahead_contact%grp_ptr) .and. &
                       same_list(contact%grp_node, ahead_contact%grp_node))) return
        end if
        same = .true.
    end function same_key

    pure logical function same_list(a, b) result(same)
        integer, allocatable, intent(in) :: a(:), b(:)
        same = allocated(a) .eqv. allocated(b)
        if (.not. (same .and. allocated(a))) return
        same = size(a) == size(b)
        if (same) same = all(a == b)
    end function same_list

    !> The coupling lists of `from` (what the pattern is made of) into `to`.
    subroutine copy_couplings(from, to)
        type(contact_t), intent(in) :: from
        type(contact_t), intent(inout) :: to
        to%nc = from%nc
        to%ngroup = from%ngroup
        call copy_list(from%cpl_ptr, to%cpl_ptr)
        call copy_list(from%cpl_node, to%cpl_node)
        call copy_list(from%grp_ptr, to%grp_ptr)
        call copy_list(from%grp_node, to%grp_node)
    end subroutine copy_couplings

    pure subroutine copy_list(from, to)
        integer, allocatable, intent(in) :: from(:)
        integer, allocatable, intent(inout) :: to(:)
        if (allocated(to)) deallocate (to)
        if (allocated(from)) to = from
    end subroutine copy_list

    !> The multiplier scale: the largest diagonal entry of K over the largest slave node
    !> length, so that the contact entries (scale x length) are of the size of K's.
    pure real(dp) function multiplier_scale(system, contact) result(scale)
        type(system_t), intent(in) :: system
        type(contact_t), intent(in) :: contact
        real(dp) :: diagonal
        integer :: j, p
        diagonal = 0.0_dp
        do j = 1, system%dofmap%neq
            do p = system%pattern%colptr(j) + 1, system%pattern%colptr(j + 1)
                if (system%pattern%rowind(p) == j - 1) &
                    diagonal = max(diagonal, abs(system%values(p)))
            end do
        end do
        scale = max(diagonal, tiny(1.0_dp))
        if (maxval([0.0_dp, contact%wref]) > 0.0_dp) scale = scale/maxval(contact%wref)
    end function multiplier_scale

    !> Whether each slave node's normal and tangential constraints act on the free dofs:
    !> the rows restricted to the free dofs are not (nearly) zero, and the tangential row is
    !> not (nearly) parallel to the normal one (a node on a symmetry line with ux prescribed:
    !> its slip is the supports' business). A constraint that does not is left out.
    pure function constraining_rows(contact, eq) result(constrains)
        type(contact_t), intent(in) :: contact
        integer, intent(in) :: eq(:, :)
        logical, allocatable :: constrains(:, :)
        real(dp), allocatable :: rn(:), rt(:)
        real(dp) :: total, nn, tt
        integer :: c, k, node, m
        allocate (constrains(2, contact%nc))
        do c = 1, contact%nc
            m = contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)
            allocate (rn(2*m), rt(2*m))
            total = 0.0_dp
            do k = 1, m
                node = contact%cpl_node(contact%cpl_ptr(c) + k - 1)
                total = total + abs(contact%cpl_a(contact%cpl_ptr(c) + k - 1))
                rn(2*k - 1:2*k) = merge(contact%cpl_a(contact%cpl_ptr(c) + k - 1)* &
                                        contact%normal(:, c), 0.0_dp, eq(:, node) > 0)
                rt(2*k - 1:2*k) = merge(contact%cpl_a(contact%cpl_ptr(c) + k - 1)* &
                                        contact%tangent(:, c), 0.0_dp, eq(:, node) > 0)
            end do
            ! relative 1e-9: a dual multiplier's weight on a linear field's values away from
            ! its node is zero up to round-off
            nn = dot_product(rn, rn)
            tt = dot_product(rt, rt)
            constrains(1, c) = sqrt(nn) > 1.0e-9_dp*total
            constrains(2, c) = sqrt(tt) > 1.0e-9_dp*total
            if (constrains(1, c) .and. constrains(2, c)) &
                constrains(2, c) = nn*tt - dot_product(rn, rt)**2 > 1.0e-9_dp*nn*tt
            deallocate (rn, rt)
        end do
    end function constraining_rows

    !> K plus the contact rows of the current active set, factorised. With `update`, K is the
    !> one factorised last and only contact rows changed: when few did, the factorisation is
    !> updated for them (umfpack_t%update_rows, a few solves) instead of being redone.
    subroutine factorise_contact(model, system, contact, result, context, error, update)
        type(model_t), intent(in) :: model
        type(system_t), intent(inout) :: system
        type(contact_t), intent(in) :: contact
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in) :: update
        real(dp), allocatable :: ke(:, :)
        real(dp) :: t0
        logical :: done, refused
        integer :: c, g, m, attempt
        do attempt = 1, 2
            t0 = wall_seconds()
            system%values = system%k_values
            do c = 1, contact%nc
                m = 2*(contact%cpl_ptr(c + 1) - contact%cpl_ptr(c)) + 2
                allocate (ke(m, m))
                call contact_element_matrix(contact, c, &
                                            model%contact_pairs(contact%pair(c))%friction, &
                                            system%contact_scale, system%constrains(:, c), ke, &
                                            system%viscous)
                call assemble_element(system%pattern, system%values, model%mesh%nelem + c, ke)
                deallocate (ke)
            end do
            do g = 1, contact%ngroup
                m = size(contact_group_dofs(contact, g, system%dofmap%eq, system%dofmap%neq))
                allocate (ke(m, m))
                call contact_group_matrix(contact, g, model%contact_pairs(contact%pair( &
                                          contact%grp_node(contact%grp_ptr(g))))%friction, &
                                          system%contact_scale, system%constrains, ke, &
                                          system%viscous)
                call assemble_element(system%pattern, system%values, &
                                      model%mesh%nelem + contact%nc + g, ke)
                deallocate (ke)
            end do
            result%stats%t_assembly = result%stats%t_assembly + (wall_seconds() - t0)
            if (update .and. attempt == 1) then
                t0 = wall_seconds()
                call system%solver%update_rows(system%pattern, system%values, done, error, &
                                               refused)
                if (allocated(error)) then
                    error%message = context//': '//error%message
                    return
                end if
                result%stats%t_update = result%stats%t_update + (wall_seconds() - t0)
                ! a non-finite update declined before LAPACK: factorised instead, counted
                if (refused) result%stats%updates_declined = result%stats%updates_declined + 1
                if (done) then
                    result%stats%updates = result%stats%updates + 1
                    return
                end if
            end if
            call factorise_values(system, result, context, error)
            if (.not. allocated(error)) return
            if (system%viscous > 0.0_dp .or. attempt == 2 .or. &
                .not. any(contact%status == contact_slip)) call mechanism_hint()
            ! Sliding everywhere, a body held by friction alone is a mechanism of the
            ! linearised equations: regularise the slip rows and try once more.
            if (system%viscous > 0.0_dp .or. .not. any(contact%status == contact_slip) .or. &
                index(error%message, 'singular') == 0) return
            system%viscous = slip_viscosity
            result%stats%regularised = result%stats%regularised + 1
            deallocate (error)
        end do
    contains
        !> A singular matrix with frictionless sliding nodes: name them (a body held by
        !> frictionless contact alone is a mechanism, docs/cards.md CONTACT).
        subroutine mechanism_hint()
            logical, allocatable :: sliding(:)
            sliding = contact%status /= contact_stick .and. contact%placed
            do c = 1, contact%nc
                if (model%contact_pairs(contact%pair(c))%friction > 0.0_dp) sliding(c) = .false.
            end do
            if (.not. any(sliding)) return
            error%message = error%message//'; '//to_text(count(sliding))//' slave nodes '// &
                'of frictionless pairs (MU = 0) slide or are open, the first node '// &
                to_text(contact%node(findloc(sliding, .true., dim=1)))// &
                trim(merge(' (slip rows regularised)', '                        ', &
                           system%viscous > 0.0_dp))//': a body held by frictionless contact '// &
                'alone is a mechanism (hold it by BOUNDARY cards or give the pair friction)'
        end subroutine mechanism_hint
    end subroutine factorise_contact

    !> Factorise system%values (the symbolic phase once per pattern and library): by
    !> CHOLMOD when the matrix is symmetric positive definite, else by UMFPACK
    !> (cfrd_linear_solver); a matrix CHOLMOD declines is factorised by UMFPACK, counted.
    subroutine factorise_values(system, result, context, error)
        type(system_t), intent(inout) :: system
        type(stage_result_t), intent(inout) :: result
        character(len=*), intent(in) :: context
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: t1
        logical :: declined, reused
        ! CFRD_WRITE_MATRIX (a measuring aid, off by default): before the clock starts
        call write_matrix_if_asked(system%pattern, system%values, context, &
                                   result%factorisations)
        t1 = wall_seconds()
        call system%solver%choose(system%pattern, system%values, error)
        if (allocated(error)) then
            error%message = context//': '//error%message
            return
        end if
        do
            if (.not. system%solver%is_analysed()) then
                ! Symbolic factorisation once per pattern (after the first assembly, so that
                ! UMFPACK sees the values it orders for); not beside a preparation ahead
                ! (new_system: METIS's random numbers).
                if (ahead_posted) call c_ahead_wait()
                call system%solver%analyse(system%pattern, system%values, error)
                if (allocated(error)) then
                    error%message = context//': '//error%message
                    return
                end if
                result%stats%t_symbolic = result%stats%t_symbolic + (wall_seconds() - t1)
                result%stats%analyses = result%stats%analyses + 1
                call post_ahead()
                t1 = wall_seconds()
            else if (system%prepared_ahead) then
                ! the analysis prepared ahead, on the second thread: counted as made
                result%stats%analyses = result%stats%analyses + 1
                result%stats%analyses_ahead = result%stats%analyses_ahead + 1
            end if
            system%prepared_ahead = .false.
            call system%solver%factorise(system%pattern, system%values, declined, error, &
                                         reused)
            if (allocated(error)) then
                error%message = context//': '//error%message
                return
            end if
            if (.not. declined) exit
            ! not positive definite for CHOLMOD: the same matrix to UMFPACK
            result%stats%cholesky_declined = result%stats%cholesky_declined + 1
        end do
        result%stats%t_numeric = result%stats%t_numeric + (wall_seconds() - t1)
        result%stats%rcond = system%solver%rcond()
        ! the factorisation set aside taken back: not a numeric factorisation
        if (reused) return
        result%stats%lu_nnz = system%solver%factor_nonzeros()
        if (system%solver%is_cholesky()) result%stats%cholesky = result%stats%cholesky + 1
        result%factorisations = result%factorisations + 1
    end subroutine factorise_values

end module cfrd_linear_system
