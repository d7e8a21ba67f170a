!> Numbers as text for messages.
module cfrd_strings
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: to_text, real_text, fixed_text, level_text

contains

    !> An integer without blanks: 42 -> '42'.
    pure function to_text(i) result(s)
        integer, intent(in) :: i
        character(len=:), allocatable :: s
        character(len=16) :: buffer
        write (buffer, '(i0)') i
        s = trim(buffer)
    end function to_text

    !> A real in scientific notation with 4 significant digits: '1.234E-05'.
    pure function real_text(x) result(s)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=16) :: buffer
        write (buffer, '(es10.3)') x
        s = trim(adjustl(buffer))
    end function real_text

    !> A real with 5 decimals: '0.25000'.
    pure function fixed_text(x) result(s)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=16) :: buffer
        write (buffer, '(f8.5)') x
        s = trim(adjustl(buffer))
    end function fixed_text

    !> An elevation or length with 2 decimals and no blanks: '768.00', '0.50', '-3.25'.
    pure function level_text(x) result(s)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=32) :: buffer
        write (buffer, '(f0.2)') x
        s = trim(adjustl(buffer))
        if (s(1:1) == '.') s = '0'//s
        if (len(s) > 1) then
            if (s(1:2) == '-.') s = '-0'//s(2:)
        end if
    end function level_text
end module cfrd_strings
