!> The one place where an element kind becomes an element implementation.
module cfrd_element_library
    use cfrd_error, only: error_t, fatal_error
    use cfrd_element, only: element_t
    use cfrd_quad4, only: quad4_t
    use cfrd_joint4, only: joint4_t
    use cfrd_model, only: elem_quad4, elem_quad4_shear, elem_joint_gauss, elem_joint_lobatto, &
                          axisymmetric
    implicit none
    private

    public :: make_element

contains

    !> Allocate the element implementation of kind `kind` (cfrd_model: elem_quad4, ...) for
    !> the analysis type (plane strain or axisymmetric).
    subroutine make_element(kind, analysis, element, error)
        integer, intent(in) :: kind, analysis
        class(element_t), allocatable, intent(out) :: element
        type(error_t), allocatable, intent(out) :: error
        character(len=12) :: text
        select case (kind)
        case (elem_quad4)
            allocate (element, source=quad4_t(axisymmetric=analysis == axisymmetric))
        case (elem_quad4_shear)
            allocate (element, source=quad4_t(axisymmetric=analysis == axisymmetric, &
                                              assumed_shear=.true.))
        case (elem_joint_gauss, elem_joint_lobatto)
            allocate (element, source=joint4_t(lobatto=kind == elem_joint_lobatto, &
                                               axisymmetric=analysis == axisymmetric))
        case default
            write (text, '(i0)') kind
            call fatal_error(error, 'internal: no element implementation for kind '//trim(text))
        end select
    end subroutine make_element
end module cfrd_element_library
