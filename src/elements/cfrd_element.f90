!> The one element interface (after FEAP): every element kind, solid quads and thin layers,
!> zero-thickness joints, and contact segments later, answers the same questions, so assembly and output
!> go through one loop. The element knows geometry and kinematics only; the material law's
!> tangent and stresses are handed in per integration point by the caller, so an element never
!> needs to know which law it carries.
!>
!> Arrays: x(2, nodes) nodal coordinates; u(2*nodes) nodal displacements ordered
!> (ux1, uy1, ux2, uy2, ...); dmat(ncomp, ncomp, ngauss) tangent per integration point;
!> strain and stress (ncomp, ngauss). A joint's "strains" are the relative displacements
!> (normal, tangential) and its "stresses" the tractions (sigma_n, tau).
!>
!> Geometry (issue 21): the B matrices and volume weights of a small-strain element depend
!> on its coordinates only, so `geometry` computes them once into an element_geometry_t and
!> stiffness / strains / internal_force take either that record or the coordinates x (then
!> the record is computed first): the same B, the same operations, the same bits.
module cfrd_element
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: element_t, element_geometry_t, max_components, max_element_dofs, max_points

    !> Largest number of stress components, element dofs and integration points of any kind
    !> (the quads: 4, 8, 4; a joint uses rows 1:2 and points 1:2).
    integer, parameter :: max_components = 4, max_element_dofs = 8, max_points = 4

    !> Geometry-only data of one element: B (components x dofs) and the volume weight dV
    !> (det J, times r axisymmetric; a joint's dS) at each integration point, the integration
    !> weight not included. Entries beyond the element's sizes are zero.
    type :: element_geometry_t
        real(dp) :: bee(max_components, max_element_dofs, max_points) = 0.0_dp
        real(dp) :: dv(max_points) = 0.0_dp
    end type element_geometry_t

    type, abstract :: element_t
    contains
        !> Number of nodes.
        procedure(count_i), deferred, nopass :: nodes
        !> Number of integration points.
        procedure(count_i), deferred, nopass :: gauss_points
        !> Number of stress / strain components at an integration point.
        procedure(count_i), deferred, nopass :: components
        !> B and dV at the integration points from the coordinates (element_geometry_t).
        procedure(geometry_i), deferred :: geometry
        !> Tangent stiffness: ke = sum over points of B^T D B dV.
        procedure(stiffness_i), deferred :: stiffness_geo
        procedure :: stiffness_x
        generic :: stiffness => stiffness_x, stiffness_geo
        !> Strains (or relative displacements) at the integration points.
        procedure(strains_i), deferred :: strains_geo
        procedure :: strains_x
        generic :: strains => strains_x, strains_geo
        !> Internal force: fe = sum over points of B^T sigma dV.
        procedure(internal_force_i), deferred :: internal_force_geo
        procedure :: internal_force_x
        generic :: internal_force => internal_force_x, internal_force_geo
        !> Equivalent nodal force of a body force per unit volume b(2).
        procedure(body_force_i), deferred :: body_force
        !> Consistent nodal forces of a normal pressure on the straight face xa -> xb.
        procedure(face_pressure_i), deferred :: face_pressure
        !> Global coordinates of the integration points.
        procedure(gauss_coordinates_i), deferred :: gauss_coordinates
    end type element_t

    abstract interface
        pure integer function count_i()
        end function count_i

        pure subroutine geometry_i(self, x, geo)
            import :: dp, element_t, element_geometry_t
            class(element_t), intent(in) :: self
            real(dp), intent(in) :: x(:, :)
            type(element_geometry_t), intent(out) :: geo
        end subroutine geometry_i

        pure subroutine stiffness_i(self, geo, dmat, ke)
            import :: dp, element_t, element_geometry_t
            class(element_t), intent(in) :: self
            type(element_geometry_t), intent(in) :: geo
            real(dp), intent(in) :: dmat(:, :, :)
            real(dp), intent(out) :: ke(:, :)
        end subroutine stiffness_i

        pure subroutine strains_i(self, geo, u, strain)
            import :: dp, element_t, element_geometry_t
            class(element_t), intent(in) :: self
            type(element_geometry_t), intent(in) :: geo
            real(dp), intent(in) :: u(:)
            real(dp), intent(out) :: strain(:, :)
        end subroutine strains_i

        pure subroutine internal_force_i(self, geo, stress, fe)
            import :: dp, element_t, element_geometry_t
            class(element_t), intent(in) :: self
            type(element_geometry_t), intent(in) :: geo
            real(dp), intent(in) :: stress(:, :)
            real(dp), intent(out) :: fe(:)
        end subroutine internal_force_i

        pure subroutine body_force_i(self, x, b, fe)
            import :: dp, element_t
            class(element_t), intent(in) :: self
            real(dp), intent(in) :: x(:, :), b(2)
            real(dp), intent(out) :: fe(:)
        end subroutine body_force_i

        pure subroutine face_pressure_i(self, xa, xb, p1, p2, fa, fb)
            import :: dp, element_t
            class(element_t), intent(in) :: self
            real(dp), intent(in) :: xa(2), xb(2), p1, p2
            real(dp), intent(out) :: fa(2), fb(2)
        end subroutine face_pressure_i

        pure subroutine gauss_coordinates_i(self, x, xg)
            import :: dp, element_t
            class(element_t), intent(in) :: self
            real(dp), intent(in) :: x(:, :)
            real(dp), intent(out) :: xg(:, :)
        end subroutine gauss_coordinates_i
    end interface

contains

    !> Tangent stiffness from the coordinates (the geometry computed first).
    pure subroutine stiffness_x(self, x, dmat, ke)
        class(element_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :), dmat(:, :, :)
        real(dp), intent(out) :: ke(:, :)
        type(element_geometry_t) :: geo
        call self%geometry(x, geo)
        call self%stiffness_geo(geo, dmat, ke)
    end subroutine stiffness_x

    !> Strains from the coordinates (the geometry computed first).
    pure subroutine strains_x(self, x, u, strain)
        class(element_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :), u(:)
        real(dp), intent(out) :: strain(:, :)
        type(element_geometry_t) :: geo
        call self%geometry(x, geo)
        call self%strains_geo(geo, u, strain)
    end subroutine strains_x

    !> Internal force from the coordinates (the geometry computed first).
    pure subroutine internal_force_x(self, x, stress, fe)
        class(element_t), intent(in) :: self
        real(dp), intent(in) :: x(:, :), stress(:, :)
        real(dp), intent(out) :: fe(:)
        type(element_geometry_t) :: geo
        call self%geometry(x, geo)
        call self%internal_force_geo(geo, stress, fe)
    end subroutine internal_force_x
end module cfrd_element
