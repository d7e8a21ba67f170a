!> Global bookkeeping shared by every analysis: equation numbers of the active mesh, element
!> dof lists, the element implementations, external loads, and the loops that assemble the
!> tangent stiffness and the internal forces through the one element interface.
module cfrd_assembly
    use cfrd_kinds, only: dp
    use cfrd_omp_threads, only: loop_threads
    use cfrd_error, only: error_t
    use cfrd_model, only: model_t, load_set_t, all_groups
    use cfrd_element, only: element_t, element_geometry_t
    use cfrd_element_library, only: make_element
    use cfrd_edge_load, only: face_pressure_forces
    use cfrd_material_law, only: nhistory, material_tangent
    use cfrd_sparse, only: sparse_pattern_t, assemble_element
    implicit none
    private

    public :: element_box_t, dof_map_t
    public :: make_elements, number_equations, load_set_forces, fill_forces
    public :: assemble_tangent, internal_forces, element_tangents, gather, active_nodes
    public :: force_memo_t, remembered_forces, remember_forces
    public :: min_parallel

    !> Elements per block of the parallel element loops: a block's contributions are
    !> computed on the OpenMP threads into storage of their own, then added in element
    !> order by one thread, so that every sum is taken in the same order for any thread
    !> count (and any block size). With threads, few blocks, few joins [choice: 4096
    !> element matrices, 8 MB; with 256 a 2-thread run on a loaded machine took 3.6 times
    !> as long as 1 thread]; with one thread, blocks whose matrices stay in the cache
    !> [choice: 128, 256 kB] (docs/performance.md (m)).
    integer, parameter :: block_size = 4096, serial_block_size = 128
    !> Fewer elements than this run on one thread: the threads' start would cost more
    !> [choice].
    integer, parameter :: min_parallel = 32

    !> One element implementation per element kind used by the mesh, and the geometry of
    !> the mesh's elements of that kind, computed once (issue 21; the mesh's coordinates do
    !> not change during an analysis: the model is intent(in) throughout, a CAST move goes
    !> to the contact's own copy): element e's record is geometry(slot(e)).
    type :: element_box_t
        class(element_t), allocatable :: element
        type(element_geometry_t), allocatable :: geometry(:)
        integer, allocatable :: slot(:)
    end type element_box_t

    !> Equation numbers of the active mesh: eq(2, nnode) > 0 for a free dof of an active node,
    !> 0 otherwise; dof_ptr / dofs list each element's equation numbers (all 0 for an inactive
    !> element), as the sparse pattern wants them.
    type :: dof_map_t
        integer :: neq = 0
        integer, allocatable :: eq(:, :)
        integer, allocatable :: dof_ptr(:)
        integer, allocatable :: dofs(:)
    end type dof_map_t

    !> The internal forces of one set of stresses on one set of active elements, kept for
    !> the next call with the same inputs, bit for bit (issue 21, docs/performance.md (aj)):
    !> an increment's predictor and midpoint corrector both take the forces of its start
    !> stresses, which are the end stresses of the increment before, whose forces its
    !> residual took.
    type :: force_memo_t
        logical, allocatable :: active(:)
        real(dp), allocatable :: stress(:, :, :)
        real(dp), allocatable :: force(:, :)
    end type force_memo_t

contains

    !> internal_forces, or the forces `memo` holds when its stresses and active elements are
    !> these, to the last bit; the forces computed are kept in `memo`.
    subroutine remembered_forces(model, library, active, stress, force, memo)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: stress(:, :, :)
        real(dp), intent(out) :: force(:, :)
        type(force_memo_t), intent(inout) :: memo
        if (remembers(memo, active, stress)) then
            force = memo%force
            return
        end if
        call internal_forces(model, library, active, stress, force)
        call remember_forces(memo, active, stress, force)
    end subroutine remembered_forces

    !> Keep `force`, the internal forces of `stress` on `active`, in `memo`.
    pure subroutine remember_forces(memo, active, stress, force)
        type(force_memo_t), intent(inout) :: memo
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: stress(:, :, :), force(:, :)
        memo%active = active
        memo%stress = stress
        memo%force = force
    end subroutine remember_forces

    !> Whether `memo` holds the forces of exactly these stresses and active elements.
    pure logical function remembers(memo, active, stress)
        type(force_memo_t), intent(in) :: memo
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: stress(:, :, :)
        remembers = .false.
        if (.not. allocated(memo%force)) return
        if (size(memo%active) /= size(active)) return
        if (any(shape(memo%stress) /= shape(stress))) return
        if (any(memo%active .neqv. active)) return
        remembers = all(memo%stress == stress)
    end function remembers

    !> The implementation of every element kind the mesh uses, indexed by kind, with the
    !> geometry (B, dV) of every element of the mesh, active or not.
    subroutine make_elements(model, library, error)
        type(model_t), intent(in) :: model
        type(element_box_t), allocatable, intent(out) :: library(:)
        type(error_t), allocatable, intent(out) :: error
        integer :: kind, e, nn, n
        allocate (library(maxval(model%mesh%kind)))
        do kind = 1, size(library)
            if (.not. any(model%mesh%kind == kind)) cycle
            call make_element(kind, model%analysis, library(kind)%element, error)
            if (allocated(error)) return
            associate (box => library(kind), mesh => model%mesh)
                allocate (box%slot(mesh%nelem), source=0)
                allocate (box%geometry(count(mesh%kind(1:mesh%nelem) == kind)))
                nn = box%element%nodes()
                n = 0
                do e = 1, mesh%nelem
                    if (mesh%kind(e) /= kind) cycle
                    n = n + 1
                    box%slot(e) = n
                    call box%element%geometry(mesh%x(:, mesh%conn(1:nn, e)), box%geometry(n))
                end do
            end associate
        end do
    end subroutine make_elements

    !> Nodes used by an active element.
    pure function active_nodes(model, active) result(used)
        type(model_t), intent(in) :: model
        logical, intent(in) :: active(:)
        logical, allocatable :: used(:)
        integer :: e
        allocate (used(model%mesh%nnode), source=.false.)
        do e = 1, model%mesh%nelem
            if (active(e)) used(model%mesh%conn(:, e)) = .true.
        end do
    end function active_nodes

    !> Number the free dofs of the active nodes node by node; list each element's equations.
    subroutine number_equations(model, library, active, dofmap)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        type(dof_map_t), intent(out) :: dofmap
        logical, allocatable :: used(:)
        integer :: node, k, e, nn, pos
        associate (mesh => model%mesh)
            used = active_nodes(model, active)
            allocate (dofmap%eq(2, mesh%nnode), source=0)
            dofmap%neq = 0
            do node = 1, mesh%nnode
                if (.not. used(node)) cycle
                do k = 1, 2
                    if (model%fixed(k, node)) cycle
                    dofmap%neq = dofmap%neq + 1
                    dofmap%eq(k, node) = dofmap%neq
                end do
            end do
            allocate (dofmap%dof_ptr(mesh%nelem + 1))
            dofmap%dof_ptr(1) = 1
            do e = 1, mesh%nelem
                nn = library(mesh%kind(e))%element%nodes()
                dofmap%dof_ptr(e + 1) = dofmap%dof_ptr(e) + 2*nn
            end do
            allocate (dofmap%dofs(dofmap%dof_ptr(mesh%nelem + 1) - 1), source=0)
            do e = 1, mesh%nelem
                if (.not. active(e)) cycle
                pos = dofmap%dof_ptr(e)
                nn = (dofmap%dof_ptr(e + 1) - pos)/2
                do k = 1, nn
                    dofmap%dofs(pos + 2*k - 2:pos + 2*k - 1) = dofmap%eq(:, mesh%conn(k, e))
                end do
            end do
        end associate
    end subroutine number_equations

    !> Nodal vector of element e from a global (2, nnode) field, ordered (x1, y1, x2, ...).
    pure function gather(model, e, nn, field) result(ue)
        type(model_t), intent(in) :: model
        integer, intent(in) :: e, nn
        real(dp), intent(in) :: field(:, :)
        real(dp) :: ue(2*nn)
        integer :: k
        do k = 1, nn
            ue(2*k - 1:2*k) = field(:, model%mesh%conn(k, e))
        end do
    end function gather

    !> Add element e's nodal vector fe to the global field.
    pure subroutine scatter_add(model, e, nn, fe, field)
        type(model_t), intent(in) :: model
        integer, intent(in) :: e, nn
        real(dp), intent(in) :: fe(:)
        real(dp), intent(inout) :: field(:, :)
        integer :: k
        do k = 1, nn
            field(:, model%mesh%conn(k, e)) = field(:, model%mesh%conn(k, e)) + fe(2*k - 1:2*k)
        end do
    end subroutine scatter_add

    !> Gravity b = gamma (ax, ay) on element e, added to force.
    subroutine add_gravity(model, library, e, ax, ay, force)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        integer, intent(in) :: e
        real(dp), intent(in) :: ax, ay
        real(dp), intent(inout) :: force(:, :)
        real(dp) :: fe(16), b(2)
        integer :: nn
        associate (mesh => model%mesh)
            nn = library(mesh%kind(e))%element%nodes()
            b = model%materials(mesh%material(e))%unit_weight*[ax, ay]
            call library(mesh%kind(e))%element%body_force(mesh%x(:, mesh%conn(1:nn, e)), b, &
                                                          fe(1:2*nn))
            call scatter_add(model, e, nn, fe(1:2*nn), force)
        end associate
    end subroutine add_gravity

    !> Forces (2, nnode) of a load set on the active elements: gravity on element groups,
    !> nodal forces, face pressures.
    subroutine load_set_forces(model, library, set, active, force)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(load_set_t), intent(in) :: set
        logical, intent(in) :: active(:)
        real(dp), intent(out) :: force(:, :)
        real(dp) :: fa(2), fb(2)
        integer :: ig, e, a, c
        associate (mesh => model%mesh)
            force = set%nodal_force
            do ig = 1, size(set%gravity)
                do e = 1, mesh%nelem
                    if (.not. active(e)) cycle
                    if (set%gravity(ig)%group /= all_groups .and. &
                        mesh%group(e) /= set%gravity(ig)%group) cycle
                    call add_gravity(model, library, e, set%gravity(ig)%ax, &
                                     set%gravity(ig)%ay, force)
                end do
            end do
            do ig = 1, size(set%pressures)
                e = set%pressures(ig)%element
                a = mesh%conn(set%pressures(ig)%face, e)
                c = mesh%conn(mod(set%pressures(ig)%face, 4) + 1, e)
                call library(mesh%kind(e))%element%face_pressure( &
                    mesh%x(:, a), mesh%x(:, c), set%pressures(ig)%p1, set%pressures(ig)%p2, &
                    fa, fb)
                force(:, a) = force(:, a) + fa
                force(:, c) = force(:, c) + fb
            end do
        end associate
    end subroutine load_set_forces

    !> The self-weight of the elements of group `group` (a FILL stage's load).
    subroutine fill_forces(model, library, group, force)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        integer, intent(in) :: group
        real(dp), intent(out) :: force(:, :)
        integer :: e
        force = 0.0_dp
        do e = 1, model%mesh%nelem
            if (model%mesh%group(e) == group) call add_gravity(model, library, e, 0.0_dp, &
                                                               -1.0_dp, force)
        end do
    end subroutine fill_forces

    !> The tangent of element e at each integration point from its stresses, total strains
    !> and history.
    pure subroutine element_tangents(model, e, stress, strain, history, dmat)
        type(model_t), intent(in) :: model
        integer, intent(in) :: e
        real(dp), intent(in) :: stress(:, :), strain(:, :), history(:, :)
        real(dp), intent(out) :: dmat(:, :, :)
        integer :: ig
        do ig = 1, size(dmat, 3)
            call material_tangent(model%materials(model%mesh%material(e)), model%pa, &
                                  stress(:, ig), strain(:, ig), history(:, ig), dmat(:, :, ig))
        end do
    end subroutine element_tangents

    !> Assemble the tangent stiffness of the active elements at the given integration-point
    !> stresses and total strains (4, ngauss, nelem) and history (nhistory, ngauss, nelem)
    !> into `values`. With `tangents` (4, 4, ngauss, nelem) given, those matrices are used
    !> instead of the material tangent (Newton's consistent tangent). The element matrices
    !> of a block of elements are computed on the OpenMP threads, then added in element
    !> order by one thread: the same sums, in the same order, for any thread count.
    subroutine assemble_tangent(model, library, active, pattern, stress, strain, history, &
                                values, tangents)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: stress(:, :, :), strain(:, :, :), history(:, :, :)
        real(dp), intent(out) :: values(:)
        real(dp), intent(in), optional :: tangents(:, :, :, :)
        real(dp), allocatable :: ke(:, :, :)
        integer, allocatable :: list(:)
        integer :: first, last, k, nn, nb
        values = 0.0_dp
        list = active_list(active)
        nb = block_elements()
        allocate (ke(16, 16, max(1, min(nb, size(list)))))
        do first = 1, size(list), nb
            last = min(first + nb - 1, size(list))
            !$omp parallel do schedule(dynamic, 16) if (last - first >= min_parallel)
            do k = first, last
                call element_stiffness(model, library, list(k), stress, strain, history, &
                                       ke(:, :, k - first + 1), tangents)
            end do
            !$omp end parallel do
            do k = first, last
                nn = library(model%mesh%kind(list(k)))%element%nodes()
                call assemble_element(pattern, values, list(k), ke(1:2*nn, 1:2*nn, k - first + 1))
            end do
        end do
    end subroutine assemble_tangent

    !> Elements per block of the element loops (block_size, serial_block_size).
    integer function block_elements()
        block_elements = block_size
        if (loop_threads() == 1) block_elements = serial_block_size
    end function block_elements

    !> The active elements in order.
    pure function active_list(active) result(list)
        logical, intent(in) :: active(:)
        integer, allocatable :: list(:)
        integer :: e
        list = pack([(e, e=1, size(active))], active)
    end function active_list

    !> The tangent stiffness ke (2 nn, 2 nn in a 16 x 16 array) of element e (assemble_tangent).
    pure subroutine element_stiffness(model, library, e, stress, strain, history, ke, tangents)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        integer, intent(in) :: e
        real(dp), intent(in) :: stress(:, :, :), strain(:, :, :), history(:, :, :)
        real(dp), intent(out) :: ke(:, :)
        real(dp), intent(in), optional :: tangents(:, :, :, :)
        real(dp) :: dmat(4, 4, 4)
        integer :: nn, ng, nc
        associate (box => library(model%mesh%kind(e)), &
                   element => library(model%mesh%kind(e))%element)
            nn = element%nodes()
            ng = element%gauss_points()
            nc = element%components()
            if (present(tangents)) then
                dmat(:, :, 1:ng) = tangents(:, :, 1:ng, e)
            else
                call element_tangents(model, e, stress(:, 1:ng, e), strain(:, 1:ng, e), &
                                      history(1:nhistory, 1:ng, e), dmat(:, :, 1:ng))
            end if
            call element%stiffness(box%geometry(box%slot(e)), dmat(1:nc, 1:nc, 1:ng), &
                                   ke(1:2*nn, 1:2*nn))
        end associate
    end subroutine element_stiffness

    !> Internal forces (2, nnode) of the active elements at the given stresses: the element
    !> vectors of a block on the OpenMP threads, added in element order by one thread (as
    !> assemble_tangent).
    subroutine internal_forces(model, library, active, stress, force, magnitude)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        logical, intent(in) :: active(:)
        real(dp), intent(in) :: stress(:, :, :)
        real(dp), intent(out) :: force(:, :)
        !> The same sums of the elements' |forces|: the scale of the round-off in `force`
        real(dp), intent(out), optional :: magnitude(:, :)
        real(dp), allocatable :: fe(:, :)
        integer, allocatable :: list(:)
        integer :: first, last, k, nn, nb
        force = 0.0_dp
        if (present(magnitude)) magnitude = 0.0_dp
        list = active_list(active)
        nb = block_elements()
        allocate (fe(16, max(1, min(nb, size(list)))))
        do first = 1, size(list), nb
            last = min(first + nb - 1, size(list))
            !$omp parallel do schedule(dynamic, 16) if (last - first >= min_parallel)
            do k = first, last
                call element_force(model, library, list(k), stress, fe(:, k - first + 1))
            end do
            !$omp end parallel do
            do k = first, last
                nn = library(model%mesh%kind(list(k)))%element%nodes()
                call scatter_add(model, list(k), nn, fe(1:2*nn, k - first + 1), force)
                if (present(magnitude)) &
                    call scatter_add(model, list(k), nn, abs(fe(1:2*nn, k - first + 1)), &
                                     magnitude)
            end do
        end do
    end subroutine internal_forces

    !> The internal force vector fe (2 nn of 16) of element e at the given stresses.
    pure subroutine element_force(model, library, e, stress, fe)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        integer, intent(in) :: e
        real(dp), intent(in) :: stress(:, :, :)
        real(dp), intent(out) :: fe(:)
        integer :: nn, ng, nc
        associate (box => library(model%mesh%kind(e)), &
                   element => library(model%mesh%kind(e))%element)
            nn = element%nodes()
            ng = element%gauss_points()
            nc = element%components()
            call element%internal_force(box%geometry(box%slot(e)), stress(1:nc, 1:ng, e), &
                                        fe(1:2*nn))
        end associate
    end subroutine element_force
end module cfrd_assembly
