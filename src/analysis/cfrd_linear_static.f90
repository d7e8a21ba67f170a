!> Linear elastic static analysis: all loads of the deck applied in one step
!> (docs/theory.md, "Linear static analysis"). Staged construction (issue 4) reuses its parts.
module cfrd_linear_static
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_clock, only: wall_seconds
    use cfrd_model, only: model_t
    use cfrd_results, only: results_t, stage_result_t
    use cfrd_sparse, only: sparse_pattern_t, build_pattern
    use cfrd_umfpack, only: umfpack_t
    use cfrd_principal, only: principal_stresses
    use cfrd_assembly, only: element_box_t, dof_map_t, make_elements, number_equations, &
                             external_forces, assemble_stiffness, elastic_tangents, gather
    implicit none
    private

    public :: solve_linear_static

contains

    !> Solve K u = f for the model's loads and prescribed displacements; return one stage with
    !> displacements, reactions and stresses.
    subroutine solve_linear_static(model, results, error)
        type(model_t), intent(in) :: model
        type(results_t), intent(out) :: results
        type(error_t), allocatable, intent(out) :: error
        type(element_box_t), allocatable :: library(:)
        type(dof_map_t) :: dofmap
        type(sparse_pattern_t) :: pattern
        type(umfpack_t) :: solver
        real(dp), allocatable :: values(:), f_ext(:, :), rhs(:, :), b(:), x(:)
        real(dp) :: t0, t1, t_start
        integer :: node, k
        character(len=*), parameter :: where = 'stage 1 (LOADS), load step 1: '

        t_start = wall_seconds()
        allocate (results%stages(1))
        associate (stage => results%stages(1), stats => results%stages(1)%stats, &
                   mesh => model%mesh)
            stage%name = 'LOADS'
            call make_elements(model, library, error)
            if (allocated(error)) return

            t0 = wall_seconds()
            call number_equations(model, library, dofmap)
            call build_pattern(pattern, dofmap%neq, dofmap%dof_ptr, dofmap%dofs, error)
            if (allocated(error)) return
            t1 = wall_seconds()
            stats%t_pattern = t1 - t0
            stats%neq = pattern%n
            stats%nnz = pattern%nnz

            t0 = wall_seconds()
            allocate (f_ext(2, mesh%nnode))
            call external_forces(model, library, f_ext)
            rhs = f_ext
            allocate (values(pattern%nnz), source=0.0_dp)
            call assemble_stiffness(model, library, pattern, values, rhs)
            allocate (b(dofmap%neq), x(dofmap%neq))
            do node = 1, mesh%nnode
                do k = 1, 2
                    if (dofmap%eq(k, node) > 0) b(dofmap%eq(k, node)) = rhs(k, node)
                end do
            end do
            stats%t_assembly = wall_seconds() - t0

            t0 = wall_seconds()
            call solver%analyse(pattern, values, error)
            if (allocated(error)) then
                error%message = where//error%message
                return
            end if
            t1 = wall_seconds()
            stats%t_symbolic = t1 - t0
            call solver%factorise(pattern, values, error)
            if (allocated(error)) then
                error%message = where//error%message
                return
            end if
            stats%t_numeric = wall_seconds() - t1
            stats%rcond = solver%rcond()
            t0 = wall_seconds()
            call solver%solve(pattern, values, b, x, error)
            if (allocated(error)) then
                error%message = where//error%message
                return
            end if
            stats%t_solve = wall_seconds() - t0
            call solver%release()
            if (.not. all(ieee_is_finite(x))) then
                call fatal_error(error, where//'the solution is not finite '// &
                                 '(singular stiffness matrix?)', numerical_error)
                return
            end if

            allocate (stage%displacement(2, mesh%nnode))
            do node = 1, mesh%nnode
                do k = 1, 2
                    if (dofmap%eq(k, node) > 0) then
                        stage%displacement(k, node) = x(dofmap%eq(k, node))
                    else
                        stage%displacement(k, node) = model%prescribed(k, node)
                    end if
                end do
            end do
            call recover(model, library, dofmap, f_ext, stage)
        end associate
        results%wall_time = wall_seconds() - t_start
    end subroutine solve_linear_static

    !> Stresses at the Gauss points and centroids, principal stresses, internal forces and
    !> from them the reactions R = f_int - f_ext at prescribed dofs.
    subroutine recover(model, library, dofmap, f_ext, stage)
        type(model_t), intent(in) :: model
        type(element_box_t), intent(in) :: library(:)
        type(dof_map_t), intent(in) :: dofmap
        real(dp), intent(in) :: f_ext(:, :)
        type(stage_result_t), intent(inout) :: stage
        real(dp), allocatable :: dmat(:, :, :), strain(:, :), stress(:, :), fe(:), f_int(:, :)
        integer :: e, nn, nc, ng, ig, k, kind
        associate (mesh => model%mesh)
            allocate (stage%stress_gauss(4, 4, mesh%nelem), source=0.0_dp)
            allocate (stage%stress_centroid(4, mesh%nelem), stage%principal(3, mesh%nelem))
            allocate (f_int(2, mesh%nnode), source=0.0_dp)
            kind = 0
            do e = 1, mesh%nelem
                if (mesh%kind(e) /= kind) then
                    kind = mesh%kind(e)
                    nn = library(kind)%element%nodes()
                    nc = library(kind)%element%components()
                    ng = library(kind)%element%gauss_points()
                    if (allocated(dmat)) deallocate (dmat, strain, stress, fe)
                    allocate (dmat(nc, nc, ng), strain(nc, ng), stress(nc, ng), fe(2*nn))
                end if
                call elastic_tangents(model, e, dmat)
                call library(kind)%element%strains(mesh%x(:, mesh%conn(1:nn, e)), &
                                                   gather(model, e, nn, stage%displacement), &
                                                   strain)
                do ig = 1, ng
                    stress(:, ig) = matmul(dmat(:, :, ig), strain(:, ig))
                end do
                call library(kind)%element%internal_force(mesh%x(:, mesh%conn(1:nn, e)), &
                                                          stress, fe)
                do k = 1, nn
                    f_int(:, mesh%conn(k, e)) = f_int(:, mesh%conn(k, e)) + fe(2*k - 1:2*k)
                end do
                stage%stress_gauss(1:nc, 1:ng, e) = stress
                ! The centroid value of Gauss-point results is their mean (as for a
                ! nonlinear law, where stresses live at the Gauss points only).
                stage%stress_centroid(:, e) = sum(stage%stress_gauss(:, 1:ng, e), dim=2)/ng
                stage%principal(:, e) = principal_stresses(stage%stress_centroid(:, e))
            end do
            stage%reaction = merge(f_int - f_ext, 0.0_dp, dofmap%eq == 0)
            stage%applied_load = sum(f_ext, dim=2)
            stage%reaction_sum = sum(stage%reaction, dim=2)
        end associate
    end subroutine recover
end module cfrd_linear_static
