!> File operations the Fortran standard lacks: atomic rename and removal, folders, bound to the C
!> library in two layers (private bind(C) interfaces, public wrappers returning error_t).
module cfrd_files
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
    use cfrd_error, only: error_t, fatal_error, io_error
    implicit none
    private

    public :: move_file, delete_file, base_name, strip_extension, make_directories, &
              is_directory

    interface
        integer(c_int) function c_rename(from, to) bind(C, name='rename')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: from(*), to(*)
        end function c_rename

        integer(c_int) function c_remove(path) bind(C, name='remove')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: path(*)
        end function c_remove

        integer(c_int) function c_mkdir(path, mode) bind(C, name='mkdir')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
        end function c_mkdir
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

    !> Whether `path` names an existing folder ('path/.' exists only for a folder).
    logical function is_directory(path)
        character(len=*), intent(in) :: path
        inquire (file=path//'/.', exist=is_directory)
    end function is_directory

    !> Create the folder `path` and any missing parents (mkdir -p); an error names the
    !> first component that could not be made.
    subroutine make_directories(path, error)
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: error
        integer(c_int) :: status
        integer :: k
        integer(c_int), parameter :: mode = int(o'777', c_int)
        do k = 2, len(path) + 1
            if (k <= len(path)) then
                if (path(k:k) /= '/') cycle
            end if
            if (is_directory(path(:k - 1))) cycle
            status = c_mkdir(path(:k - 1)//c_null_char, mode)
            if (.not. is_directory(path(:k - 1))) then
                call fatal_error(error, 'cannot create the folder '//path(:k - 1), io_error)
                return
            end if
        end do
    end subroutine make_directories

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
