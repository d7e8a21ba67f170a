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
module cfrd_element
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: element_t

    type, abstract :: element_t
    contains
        !> Number of nodes.
        procedure(count_i), deferred, nopass :: nodes
        !> Number of integration points.
        procedure(count_i), deferred, nopass :: gauss_points
        !> Number of stress / strain components at an integration point.
        procedure(count_i), deferred, nopass :: components
        !> Tangent stiffness: ke = sum over points of B^T D B dV.
        procedure(stiffness_i), deferred :: stiffness
        !> Strains (or relative displacements) at the integration points.
        procedure(strains_i), deferred :: strains
        !> Internal force: fe = sum over points of B^T sigma dV.
        procedure(internal_force_i), deferred :: internal_force
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

        pure subroutine stiffness_i(self, x, dmat, ke)
            import :: dp, element_t
            class(element_t), intent(in) :: self
            real(dp), intent(in) :: x(:, :), dmat(:, :, :)
            real(dp), intent(out) :: ke(:, :)
        end subroutine stiffness_i

        pure subroutine strains_i(self, x, u, strain)
            import :: dp, element_t
            class(element_t), intent(in) :: self
            real(dp), intent(in) :: x(:, :), u(:)
            real(dp), intent(out) :: strain(:, :)
        end subroutine strains_i

        pure subroutine internal_force_i(self, x, stress, fe)
            import :: dp, element_t
            class(element_t), intent(in) :: self
            real(dp), intent(in) :: x(:, :), stress(:, :)
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
end module cfrd_element
