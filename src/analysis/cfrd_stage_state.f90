!> The evolving state of a staged analysis, carried from increment to increment and from
!> stage to stage: displacements, Gauss-point stresses, strains and history, the active
!> elements, the applied load, the reservoir level, the creep state, the date and the
!> contact state.
module cfrd_stage_state
    use cfrd_kinds, only: dp
    use cfrd_model, only: no_date, dry_level
    use cfrd_contact, only: contact_t
    implicit none
    private

    public :: state_t, ngauss


    !> Most integration points of any element kind (quads 4, joints 2).
    integer, parameter :: ngauss = 4

    !> The evolving state: displacements since the last reset, Gauss-point stresses and
    !> history, active elements, the external load applied so far and the reservoir level.
    type :: state_t
        real(dp), allocatable :: u(:, :)             !! (2, nnode)
        real(dp), allocatable :: u_before_reset(:, :) !! (2, nnode) sum of u at the resets
        real(dp), allocatable :: stress(:, :, :)     !! (4, ngauss, nelem)
        !> (4, ngauss, nelem) total strain since placement (a joint: relative displacement)
        real(dp), allocatable :: strain(:, :, :)
        real(dp), allocatable :: history(:, :, :)    !! (nhistory, ngauss, nelem)
        logical, allocatable :: active(:)            !! (nelem)
        real(dp), allocatable :: f_ext(:, :)         !! (2, nnode) applied so far
        logical :: prescribed_done = .false.         !! BOUNDARY values applied
        real(dp) :: level = dry_level                !! reservoir level, m
        !> (ncreep, ngauss, nelem) creep strains reached (only when some material creeps)
        real(dp), allocatable :: creep(:, :, :)
        !> (4, ngauss, nelem) D times the creep (and wetting) strain of the increment being solved (the load
        !> it puts on the increment); zero outside creeping increments
        real(dp), allocatable :: creep_stress(:, :, :)
        !> (ncreep, ngauss, nelem) wetting strains reached (only when some material has a
        !> WETTING card), and the elements wetted by a WET stage so far
        real(dp), allocatable :: wet(:, :, :)
        logical, allocatable :: wetted(:)
        real(dp) :: day = no_date                    !! the date reached, day number
        logical :: has_contact = .false.             !! the deck has CONTACT pairs
        type(contact_t) :: contact                   !! their state (docs/theory.md s. 14)
    end type state_t
end module cfrd_stage_state
