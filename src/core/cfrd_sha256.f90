!> SHA-256 (FIPS 180-4, section 6.2) of a byte string or a file, as 64 lowercase hex digits,
!> the form `sha256sum` prints. It identifies the deck a results file was computed from
!> (docs/results.md, root attribute `deck_sha256`). Fortran has no unsigned 32-bit integer:
!> every word is held in a 64-bit integer in [0, 2**32) and sums are masked back, so that
!> nothing overflows.
module cfrd_sha256
    use, intrinsic :: iso_fortran_env, only: int64
    use cfrd_error, only: error_t, fatal_error, io_error
    implicit none
    private

    public :: sha256_hex, file_sha256

    integer(int64), parameter :: mask32 = 4294967295_int64     !! 2**32 - 1

    !> The first 32 bits of the fractional parts of the cube roots of the first 64 primes.
    integer(int64), parameter :: round_constant(0:63) = [ &
        int(z'428a2f98', int64), int(z'71374491', int64), int(z'b5c0fbcf', int64), &
        int(z'e9b5dba5', int64), int(z'3956c25b', int64), int(z'59f111f1', int64), &
        int(z'923f82a4', int64), int(z'ab1c5ed5', int64), int(z'd807aa98', int64), &
        int(z'12835b01', int64), int(z'243185be', int64), int(z'550c7dc3', int64), &
        int(z'72be5d74', int64), int(z'80deb1fe', int64), int(z'9bdc06a7', int64), &
        int(z'c19bf174', int64), int(z'e49b69c1', int64), int(z'efbe4786', int64), &
        int(z'0fc19dc6', int64), int(z'240ca1cc', int64), int(z'2de92c6f', int64), &
        int(z'4a7484aa', int64), int(z'5cb0a9dc', int64), int(z'76f988da', int64), &
        int(z'983e5152', int64), int(z'a831c66d', int64), int(z'b00327c8', int64), &
        int(z'bf597fc7', int64), int(z'c6e00bf3', int64), int(z'd5a79147', int64), &
        int(z'06ca6351', int64), int(z'14292967', int64), int(z'27b70a85', int64), &
        int(z'2e1b2138', int64), int(z'4d2c6dfc', int64), int(z'53380d13', int64), &
        int(z'650a7354', int64), int(z'766a0abb', int64), int(z'81c2c92e', int64), &
        int(z'92722c85', int64), int(z'a2bfe8a1', int64), int(z'a81a664b', int64), &
        int(z'c24b8b70', int64), int(z'c76c51a3', int64), int(z'd192e819', int64), &
        int(z'd6990624', int64), int(z'f40e3585', int64), int(z'106aa070', int64), &
        int(z'19a4c116', int64), int(z'1e376c08', int64), int(z'2748774c', int64), &
        int(z'34b0bcb5', int64), int(z'391c0cb3', int64), int(z'4ed8aa4a', int64), &
        int(z'5b9cca4f', int64), int(z'682e6ff3', int64), int(z'748f82ee', int64), &
        int(z'78a5636f', int64), int(z'84c87814', int64), int(z'8cc70208', int64), &
        int(z'90befffa', int64), int(z'a4506ceb', int64), int(z'bef9a3f7', int64), &
        int(z'c67178f2', int64)]

    !> The first 32 bits of the fractional parts of the square roots of the first 8 primes.
    integer(int64), parameter :: initial_hash(8) = [ &
        int(z'6a09e667', int64), int(z'bb67ae85', int64), int(z'3c6ef372', int64), &
        int(z'a54ff53a', int64), int(z'510e527f', int64), int(z'9b05688c', int64), &
        int(z'1f83d9ab', int64), int(z'5be0cd19', int64)]

contains

    !> The SHA-256 digest of the bytes of `message` (each character one byte).
    pure function sha256_hex(message) result(hex)
        character(len=*), intent(in) :: message
        character(len=64) :: hex
        character(len=*), parameter :: digits = '0123456789abcdef'
        character(len=128) :: tail
        integer(int64) :: hash(8), bits
        integer :: n, full, rest, tail_blocks, i, k, nibble
        hash = initial_hash
        n = len(message)
        full = n/64
        do i = 0, full - 1
            call compress(hash, message(64*i + 1:64*i + 64))
        end do
        ! Padding (section 5.1.1): the rest, a 1 bit, zeros, the length in bits in 64 bits
        ! big-endian; one block when the rest leaves room for the 9 bytes, else two.
        rest = n - 64*full
        tail = repeat(char(0), len(tail))
        tail(1:rest) = message(64*full + 1:n)
        tail(rest + 1:rest + 1) = char(128)
        tail_blocks = merge(1, 2, rest < 56)
        bits = 8_int64*int(n, int64)
        do k = 0, 7
            i = 64*tail_blocks - k
            tail(i:i) = char(int(iand(shiftr(bits, 8*k), 255_int64)))
        end do
        call compress(hash, tail(1:64))
        if (tail_blocks == 2) call compress(hash, tail(65:128))
        do i = 1, 8
            do k = 1, 8
                nibble = int(iand(shiftr(hash(i), 4*(8 - k)), 15_int64))
                hex(8*(i - 1) + k:8*(i - 1) + k) = digits(nibble + 1:nibble + 1)
            end do
        end do
    end function sha256_hex

    !> The SHA-256 digest of the file at `path`, byte for byte (what `sha256sum` prints).
    subroutine file_sha256(path, hex, error)
        character(len=*), intent(in) :: path
        character(len=64), intent(out) :: hex
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: bytes
        character(len=256) :: msg
        integer :: unit, stat, size_bytes
        hex = ''
        open (newunit=unit, file=path, access='stream', form='unformatted', action='read', &
              status='old', iostat=stat, iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, 'cannot read '//path//': '//trim(msg), io_error)
            return
        end if
        inquire (unit=unit, size=size_bytes)
        allocate (character(len=max(size_bytes, 0)) :: bytes)
        if (size_bytes > 0) read (unit, iostat=stat, iomsg=msg) bytes
        close (unit)
        if (size_bytes < 0 .or. stat /= 0) then
            call fatal_error(error, 'cannot read '//path//': '//trim(msg), io_error)
            return
        end if
        hex = sha256_hex(bytes)
    end subroutine file_sha256

    !> One 64-byte block into the hash (section 6.2.2).
    pure subroutine compress(hash, block)
        integer(int64), intent(inout) :: hash(8)
        character(len=64), intent(in) :: block
        integer(int64) :: w(0:63), v(8), sigma0, sigma1, choice, majority, t1, t2
        integer :: t
        do t = 0, 15
            w(t) = ior(ior(shiftl(byte(4*t + 1), 24), shiftl(byte(4*t + 2), 16)), &
                       ior(shiftl(byte(4*t + 3), 8), byte(4*t + 4)))
        end do
        do t = 16, 63
            sigma0 = ieor(ieor(rotr(w(t - 15), 7), rotr(w(t - 15), 18)), shiftr(w(t - 15), 3))
            sigma1 = ieor(ieor(rotr(w(t - 2), 17), rotr(w(t - 2), 19)), shiftr(w(t - 2), 10))
            w(t) = iand(w(t - 16) + sigma0 + w(t - 7) + sigma1, mask32)
        end do
        ! v = a, b, c, d, e, f, g, h of the standard
        v = hash
        do t = 0, 63
            sigma1 = ieor(ieor(rotr(v(5), 6), rotr(v(5), 11)), rotr(v(5), 25))
            choice = ieor(iand(v(5), v(6)), iand(ieor(v(5), mask32), v(7)))
            t1 = iand(v(8) + sigma1 + choice + round_constant(t) + w(t), mask32)
            sigma0 = ieor(ieor(rotr(v(1), 2), rotr(v(1), 13)), rotr(v(1), 22))
            majority = ieor(ieor(iand(v(1), v(2)), iand(v(1), v(3))), iand(v(2), v(3)))
            t2 = iand(sigma0 + majority, mask32)
            v(8) = v(7)
            v(7) = v(6)
            v(6) = v(5)
            v(5) = iand(v(4) + t1, mask32)
            v(4) = v(3)
            v(3) = v(2)
            v(2) = v(1)
            v(1) = iand(t1 + t2, mask32)
        end do
        hash = iand(hash + v, mask32)
    contains
        pure integer(int64) function byte(i)
            integer, intent(in) :: i
            byte = int(ichar(block(i:i)), int64)
        end function byte
    end subroutine compress

    !> Rotate the 32-bit word `x` right by `n` bits.
    elemental integer(int64) function rotr(x, n)
        integer(int64), intent(in) :: x
        integer, intent(in) :: n
        rotr = iand(ior(shiftr(x, n), shiftl(x, 32 - n)), mask32)
    end function rotr
end module cfrd_sha256
