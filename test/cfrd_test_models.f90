!> Small models built in code for the verification tests, so that the analysis is checked
!> independently of the deck reader.
module cfrd_test_models
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, material_t, pressure_load_t, elem_quad4, law_goodman
    implicit none
    private

    public :: new_model, elastic_material, add_pressure, relative_imbalance, edge_traction
    public :: linear_joint

contains

    !> A model with the given nodes, elements and materials; no constraints and no loads yet.
    subroutine new_model(model, x, conn, material, materials)
        type(model_t), intent(out) :: model
        real(dp), intent(in) :: x(:, :)
        integer, intent(in) :: conn(:, :), material(:)
        type(material_t), intent(in) :: materials(:)
        model%deck_file = 'test'
        model%deck_text = ''
        model%title = 'verification model'
        model%units = 'KN-M'
        model%mesh%nnode = size(x, 2)
        model%mesh%nelem = size(conn, 2)
        model%mesh%x = x
        model%mesh%conn = conn
        model%mesh%material = material
        allocate (model%mesh%kind(model%mesh%nelem), source=elem_quad4)
        allocate (model%mesh%group(model%mesh%nelem), source=0)
        allocate (model%mesh%group_name(0))
        model%materials = materials
        allocate (model%fixed(2, model%mesh%nnode), source=.false.)
        allocate (model%prescribed(2, model%mesh%nnode), source=0.0_dp)
        allocate (model%load_sets(1), model%stages(1))
        allocate (model%load_sets(1)%nodal_force(2, model%mesh%nnode), source=0.0_dp)
        allocate (model%load_sets(1)%gravity(0), model%load_sets(1)%pressures(0))
        model%stages(1)%label = 'LOADS'
    end subroutine new_model

    pure function elastic_material(e, nu, unit_weight) result(mat)
        real(dp), intent(in) :: e, nu, unit_weight
        type(material_t) :: mat
        mat%label = 'elastic'
        mat%youngs_modulus = e
        mat%poisson_ratio = nu
        mat%unit_weight = unit_weight
    end function elastic_material

    !> A Goodman material with constant stiffnesses: n1 = 0 and Rf1 = 0 make ks = k1 gamma_w.
    pure function linear_joint(kn, ks) result(mat)
        real(dp), intent(in) :: kn, ks
        type(material_t) :: mat
        mat%law = law_goodman
        mat%label = 'joint'
        mat%kn_compression = kn
        mat%kn_tension = kn
        mat%k1 = ks/9.81_dp
        mat%gamma_w = 9.81_dp
        mat%n1 = 0.0_dp
        mat%rf1 = 0.0_dp
        mat%phi = 45.0_dp
        mat%sigma_n_floor = 10.0_dp
    end function linear_joint

    subroutine add_pressure(model, element, face, p1, p2)
        type(model_t), intent(inout) :: model
        integer, intent(in) :: element, face
        real(dp), intent(in) :: p1, p2
        associate (set => model%load_sets(1))
            set%pressures = [set%pressures, pressure_load_t(element, face, p1, p2)]
        end associate
    end subroutine add_pressure

    !> |applied + reactions| / |applied|, the equilibrium of the whole model.
    pure real(dp) function relative_imbalance(applied, reactions)
        real(dp), intent(in) :: applied(2), reactions(2)
        relative_imbalance = norm2(applied + reactions)/max(norm2(applied), tiny(1.0_dp))
    end function relative_imbalance

    !> Nodal forces of a uniform traction t(2) on the straight edge through `nodes` (in
    !> order; each segment's force split half and half), added to force.
    subroutine edge_traction(model, nodes, t, force)
        type(model_t), intent(in) :: model
        integer, intent(in) :: nodes(:)
        real(dp), intent(in) :: t(2)
        real(dp), intent(inout) :: force(:, :)
        real(dp) :: length
        integer :: k
        do k = 1, size(nodes) - 1
            length = norm2(model%mesh%x(:, nodes(k + 1)) - model%mesh%x(:, nodes(k)))
            force(:, nodes(k)) = force(:, nodes(k)) + 0.5_dp*length*t
            force(:, nodes(k + 1)) = force(:, nodes(k + 1)) + 0.5_dp*length*t
        end do
    end subroutine edge_traction
end module cfrd_test_models
