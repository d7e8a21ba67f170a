!> Tests of io_deck (placeholder until its suite lands).
module test_io_deck
    use cfrd_testing, only: unittest_t
    implicit none
    private
    public :: collect_io_deck
contains
    subroutine collect_io_deck(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        allocate (tests(0))
    end subroutine collect_io_deck
end module test_io_deck
