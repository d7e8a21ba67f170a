!> File operations the Fortran standard lacks: atomic rename and removal, bound to the C
!> library in two layers (private bind(C) interfaces, public wrappers returning error_t).
module cfrd_files
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
    use cfrd_error, only: error_t, fatal_error, io_error
    implicit none
    private

    public :: move_file, delete_file, base_name, strip_extension

    interface
        integer(c_int) function c_rename(from, to) bind(C, name='rename')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: from(*), to(*)
        end function c_rename

        integer(c_int) function c_remove(path) bind(C, name='remove')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: path(*)
        end function c_remove
    end interface

contains

    !> Rename `from` to `to`, replacing `to` atomically (POSIX rename on one file system).
    subroutine move_file(from, to, error)
        character(len=*), intent(in) :: from, to
        type(error_t), allocatable, intent(out) :: error
        if (c_rename(from//c_null_char, to//c_null_char) /= 0) then
            call fatal_error(error, 'cannot rename '//from//' to '//to, io_error)
        end if
    end subroutine move_file

    !> Remove a file if it exists; silent otherwise (used to clean up temporary files).
    subroutine delete_file(path)
        character(len=*), intent(in) :: path
        integer(c_int) :: status
        status = c_remove(path//c_null_char)
    end subroutine delete_file

    !> The last component of a path: 'inputs/dam.dat' -> 'dam.dat'.
    pure function base_name(path) result(name)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: name
        name = path(index(path, '/', back=.true.) + 1:)
    end function base_name

    !> The path without its extension: 'inputs/dam.dat' -> 'inputs/dam'.
    pure function strip_extension(path) result(stem)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: stem
        integer :: dot, slash
        dot = index(path, '.', back=.true.)
        slash = index(path, '/', back=.true.)
        if (dot > slash + 1) then
            stem = path(:dot - 1)
        else
            stem = path
        end if
    end function strip_extension
end module cfrd_files
