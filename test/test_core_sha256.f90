!> SHA-256 (src/core/cfrd_sha256.f90) against published digests: the FIPS 180-4 examples
!> (NIST, "Cryptographic Standards and Guidelines: Examples with Intermediate Values",
!> SHA256.pdf: "abc", the 448-bit two-block message; SHA-2 additional test vectors: the
!> empty message, the 896-bit message, one million 'a'), and digests printed by an
!> independent implementation (Python's hashlib, OpenSSL) for the padding boundaries (55, 56
!> and 64 bytes: one or two padding blocks) and for bytes above 127. A file's digest is
!> checked against the digest of the same bytes in memory.
module test_core_sha256
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_sha256, only: sha256_hex, file_sha256
    implicit none
    private

    public :: collect_core_sha256

contains

    subroutine collect_core_sha256(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('fips_180_4_vectors', test_fips), &
                new_unittest('padding_boundaries_and_high_bytes', test_boundaries), &
                new_unittest('file_digest', test_file) &
                ]
    end subroutine collect_core_sha256

    subroutine test_fips(error)
        type(error_t), allocatable, intent(out) :: error
        call check(error, sha256_hex('abc'), &
                   'ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad', '"abc"')
        if (allocated(error)) return
        call check(error, sha256_hex('abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq'), &
                   '248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1', &
                   'the 448-bit message')
        if (allocated(error)) return
        call check(error, sha256_hex(''), &
                   'e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855', &
                   'the empty message')
        if (allocated(error)) return
        call check(error, sha256_hex('abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmn'// &
                                     'hijklmnoijklmnopjklmnopqklmnopqrlmnopqrsmnopqrstnopqrstu'), &
                   'cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1', &
                   'the 896-bit message')
        if (allocated(error)) return
        call check(error, sha256_hex(repeat('a', 1000000)), &
                   'cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0', &
                   "one million 'a'")
    end subroutine test_fips

    subroutine test_boundaries(error)
        type(error_t), allocatable, intent(out) :: error
        character(len=256) :: all_bytes
        integer :: i
        call check(error, sha256_hex(repeat('a', 55)), &
                   '9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318', &
                   "55 'a': the length fits the last block")
        if (allocated(error)) return
        call check(error, sha256_hex(repeat('a', 56)), &
                   'b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a', &
                   "56 'a': a second padding block")
        if (allocated(error)) return
        call check(error, sha256_hex(repeat('a', 64)), &
                   'ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb', &
                   "64 'a': a whole block, then padding")
        if (allocated(error)) return
        do i = 0, 255
            all_bytes(i + 1:i + 1) = char(i)
        end do
        call check(error, sha256_hex(all_bytes), &
                   '40aff2e9d2d8922e47afd4648e6967497158785fbd1da870e7110266bf944880', &
                   'the bytes 0 to 255')
    end subroutine test_boundaries

    !> A file of 300 bytes (bytes above 127, line ends, a NUL) hashes as its bytes do.
    subroutine test_file(error)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), parameter :: path = 'build/test-sha256.bin'
        character(len=300) :: bytes
        character(len=64) :: hex
        integer :: unit, i
        logical :: refused
        do i = 1, 300
            bytes(i:i) = char(mod(7*i + 3, 256))
        end do
        open (newunit=unit, file=path, access='stream', form='unformatted', status='replace', &
              action='write')
        write (unit) bytes
        close (unit)
        call file_sha256(path, hex, error)
        if (allocated(error)) return
        call check(error, hex, sha256_hex(bytes), 'the file against its bytes')
        if (allocated(error)) return
        open (newunit=unit, file=path, status='old')
        close (unit, status='delete')
        call file_sha256(path, hex, error)
        refused = allocated(error)
        call check(error, refused, 'a missing file is an error')
    end subroutine test_file
end module test_core_sha256
