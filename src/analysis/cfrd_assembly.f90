!> Global bookkeeping shared by every analysis: equation numbers, element dof lists, the
!> element implementations, external loads, and the loop that assembles the stiffness or the
!> internal forces through the one element interface.
module cfrd_assembly
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_model, only: model_t, all_groups
    use cfrd_element, only: element_t
    use cfrd_element_library, only: make_element
    use cfrd_edge_load, only: face_pressure_forces
    use cfrd_elastic, only: elastic_dmatrix
    use cfrd_sparse, only: sparse_pattern_t, assemble_element
    implicit none
    private

    public :: element_box_t, dof_map_t
    public :: make_elements, number_equations, external_forces
    public :: assemble_stiffness, elastic_tangents, gather

    !> One element implementation per element kind used by the mesh.
    type :: element_box_t
        class(element_t), allocatable :: element
    end type element_box_t

    !> Equation numbers: eq(2, nnode) > 0 for a free dof, 0 for a prescribed one;
    !> dof_ptr / dofs list each element's equation numbers, as the sparse pattern wants them.
    type :: dof_map_t
        integer :: neq = 0
        integer, allocatable :: eq(:, :)
        integer, allocatable :: dof_ptr(:)
        integer, allocatable :: dofs(:)
    end type dof_map_t

contains

    !> The implementation of every element kind the mesh uses, indexed by kind.
    subroutine make_elements(model, library, error)
        type(model_t), intent(in) :: model
        type(element_box_t), allocatable, intent(out) :: library(:)
        type(error_t), allocatable, intent(out) :: error
        integer :: kind
        allocate (library(maxval(model%mesh%kind)))
        do kind = 1, size(library)
            if (.not. any(model%mesh%kind == kind)) cycle
            call make_element(kind, library(kind)%element, error)
            if (allocated(error)) return
        end do
    end subroutine make_elements

    !> Number the free dofs node by node; list each element's equation numbers.
    subroutine number_equations(model, library, dofmap)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(dof_map_t), intent(out) :: dofmap
        integer :: node, k, e, nn, pos
        associate (mesh => model%mesh)
            allocate (dofmap%eq(2, mesh%nnode))
            dofmap%neq = 0
            do node = 1, mesh%nnode
                do k = 1, 2
                    if (model%fixed(k, node)) then
                        dofmap%eq(k, node) = 0
                    else
                        dofmap%neq = dofmap%neq + 1
                        dofmap%eq(k, node) = dofmap%neq
                    end if
                end do
            end do
            allocate (dofmap%dof_ptr(mesh%nelem + 1))
            dofmap%dof_ptr(1) = 1
            do e = 1, mesh%nelem
                nn = library(mesh%kind(e))%element%nodes()
                dofmap%dof_ptr(e + 1) = dofmap%dof_ptr(e) + 2*nn
            end do
            allocate (dofmap%dofs(dofmap%dof_ptr(mesh%nelem + 1) - 1))
            do e = 1, mesh%nelem
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

    !> External forces (2, nnode): gravity on element groups, nodal forces, face pressures.
    subroutine external_forces(model, library, force)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        real(dp), intent(out) :: force(:, :)
        real(dp), allocatable :: fe(:)
        real(dp) :: b(2), fa(2), fb(2)
        integer :: ig, e, nn, k, a, c
        associate (mesh => model%mesh)
            force = model%nodal_force
            do ig = 1, size(model%gravity)
                do e = 1, mesh%nelem
                    if (model%gravity(ig)%group /= all_groups .and. &
                        mesh%group(e) /= model%gravity(ig)%group) cycle
                    nn = library(mesh%kind(e))%element%nodes()
                    b = model%materials(mesh%material(e))%unit_weight* &
                        [model%gravity(ig)%ax, model%gravity(ig)%ay]
                    if (allocated(fe)) deallocate (fe)
                    allocate (fe(2*nn))
                    call library(mesh%kind(e))%element%body_force( &
                        mesh%x(:, mesh%conn(1:nn, e)), b, fe)
                    do k = 1, nn
                        force(:, mesh%conn(k, e)) = force(:, mesh%conn(k, e)) + fe(2*k - 1:2*k)
                    end do
                end do
            end do
            do ig = 1, size(model%pressures)
                e = model%pressures(ig)%element
                a = mesh%conn(model%pressures(ig)%face, e)
                c = mesh%conn(mod(model%pressures(ig)%face, 4) + 1, e)
                call face_pressure_forces(mesh%x(:, a), mesh%x(:, c), model%pressures(ig)%p1, &
                                          model%pressures(ig)%p2, fa, fb)
                force(:, a) = force(:, a) + fa
                force(:, c) = force(:, c) + fb
            end do
        end associate
    end subroutine external_forces

    !> The linear elastic tangent of element e at each of its ngauss points.
    pure subroutine elastic_tangents(model, e, dmat)
        type(model_t), intent(in) :: model
        integer, intent(in) :: e
        real(dp), intent(out) :: dmat(:, :, :)
        integer :: ig
        associate (mat => model%materials(model%mesh%material(e)))
            do ig = 1, size(dmat, 3)
                dmat(:, :, ig) = elastic_dmatrix(mat%youngs_modulus, mat%poisson_ratio)
            end do
        end associate
    end subroutine elastic_tangents

    !> Assemble the elastic stiffness into `values` (pattern's layout) and, for prescribed
    !> dofs with non-zero values, move K_fp u_p to the right-hand side: force -= K u_p.
    subroutine assemble_stiffness(model, library, pattern, values, force)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(inout) :: values(:)
        real(dp), intent(inout) :: force(:, :)
        real(dp), allocatable :: ke(:, :), dmat(:, :, :), up(:), fp(:)
        real(dp), allocatable :: u_prescribed(:, :)
        integer :: e, nn, nc, ng, k, kind
        logical :: any_prescribed
        associate (mesh => model%mesh)
            u_prescribed = merge(model%prescribed, 0.0_dp, model%fixed)
            any_prescribed = any(u_prescribed /= 0.0_dp)
            kind = 0
            do e = 1, mesh%nelem
                if (mesh%kind(e) /= kind) then
                    ! (Re)size work arrays only when the element kind changes.
                    kind = mesh%kind(e)
                    nn = library(kind)%element%nodes()
                    nc = library(kind)%element%components()
                    ng = library(kind)%element%gauss_points()
                    if (allocated(ke)) deallocate (ke, dmat, up, fp)
                    allocate (ke(2*nn, 2*nn), dmat(nc, nc, ng), up(2*nn), fp(2*nn))
                end if
                call elastic_tangents(model, e, dmat)
                call library(kind)%element%stiffness(mesh%x(:, mesh%conn(1:nn, e)), dmat, ke)
                call assemble_element(pattern, values, e, ke)
                if (any_prescribed) then
                    up = gather(model, e, nn, u_prescribed)
                    if (any(up /= 0.0_dp)) then
                        fp = matmul(ke, up)
                        do k = 1, nn
                            force(:, mesh%conn(k, e)) = force(:, mesh%conn(k, e)) &
                                                        - fp(2*k - 1:2*k)
                        end do
                    end if
                end if
            end do
        end associate
    end subroutine assemble_stiffness
end module cfrd_assembly
