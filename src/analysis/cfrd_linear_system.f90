!> The linear-algebra objects of one active set of elements (and contact pairs): the
!> equation numbering, the sparse pattern, the tangent's values and UMFPACK's factors,
!> with the symbolic factorisation kept while the pattern holds (docs/theory.md section 9).
!> With contact, the multiplier rows of the current active set are added to K before each
!> factorisation, or the factors updated for the rows that changed (section 14).
module cfrd_linear_system
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
    public :: slip_viscosity


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
    end type system_t

    !> The slip rows' regularisation when a body held by friction alone slips at every
    !> node (a mechanism of the linearised equations): q = mu p sign - 1e-9 c_n slip.
    real(dp), parameter :: slip_viscosity = 1.0e-9_dp
    !> From this many equations on, UMFPACK orders a contact system by METIS instead of AMD:
    !> at x4 (20,818) and x8 (82,594) its numeric factorisations save more than its dearer
    !> analyses cost, at x2 (5,000) they do not [choice, measured: docs/performance.md (ab)].
    integer, parameter :: contact_metis_min = 10000

contains

    !> Equations, pattern and a fresh solver for the current active set.
    !> With contact, each slave node is one more element (its coupled nodes and its two
    !> multiplier equations, numbered after the displacement equations).
    subroutine new_system(model, library, active, system, error, contact, has_contact)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        type(system_t), intent(inout) :: system
        type(error_t), allocatable, intent(out) :: error
        type(contact_t), intent(in) :: contact
        logical, intent(in) :: has_contact
        integer, allocatable :: dof_ptr(:), dofs(:), more(:)
        integer :: c, g, k, nelem, pos
        call system%solver%release()
        call system%solver%configure(model%linear_solver, .not. has_contact, &
                                     all_linear(model, active), &
                                     multipliers=merge(2*contact%nc, 0, has_contact))
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
            system%constrains = constraining_rows(contact, system%dofmap%eq)
            ! The multipliers are scaled to K's size (multiplier_scale): UMFPACK's row
            ! scaling would only push its pivots off the diagonal.
            call system%solver%set_row_scaling(.false.)
            ! METIS on the larger systems; no iterative refinement of the solves of the
            ! factorised matrix: the updated solves refine against the matrix they solve
            ! (docs/theory.md section 6, docs/performance.md (ab)).
            call system%solver%set_metis(system%pattern%n >= contact_metis_min)
            call system%solver%set_refinement(.false.)
        else
            call build_pattern(system%pattern, system%dofmap%neq, system%dofmap%dof_ptr, &
                               system%dofmap%dofs, error)
        end if
        if (allocated(error)) return
        if (allocated(system%k_values)) deallocate (system%k_values)
        if (allocated(system%values)) deallocate (system%values)
        allocate (system%values(system%pattern%nnz), source=0.0_dp)
        system%factorised_linear = .false.
        system%scale_given = .false.
        system%start_kept = .false.
    end subroutine new_system

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
                ! UMFPACK sees the values it orders for).
                call system%solver%analyse(system%pattern, system%values, error)
                if (allocated(error)) then
                    error%message = context//': '//error%message
                    return
                end if
                result%stats%t_symbolic = result%stats%t_symbolic + (wall_seconds() - t1)
                result%stats%analyses = result%stats%analyses + 1
                t1 = wall_seconds()
            end if
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
