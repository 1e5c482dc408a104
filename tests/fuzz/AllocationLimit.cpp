// Linked into the frame-source fuzzers: the process runs as on a machine where one allocation of
// more than 256 MB fails with std::bad_alloc. MRPT 2.5's deserializer trusts the sizes it reads
// (a flipped bit in a string length asks for up to 4 GB before the read fails), and a sanitizer
// reports such a request instead of failing it; the readers must survive the failure, which is
// what a memory-limited robot computer gives them. Legitimate allocations (frames, images) are
// a few MB. The aligned forms stay the sanitizer's own.
#include <cstdlib>
#include <new>

namespace
{
constexpr std::size_t kLimit = std::size_t{256} << 20;

void* allocate(std::size_t n)
{
    if (n > kLimit)
        throw std::bad_alloc();
    if (void* p = std::malloc(n == 0 ? 1 : n))
        return p;
    throw std::bad_alloc();
}

void* allocateOrNull(std::size_t n) noexcept
{
    return n > kLimit ? nullptr : std::malloc(n == 0 ? 1 : n);
}
}  // namespace

void* operator new(std::size_t n)
{
    return allocate(n);
}
void* operator new[](std::size_t n)
{
    return allocate(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept
{
    return allocateOrNull(n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept
{
    return allocateOrNull(n);
}
void operator delete(void* p) noexcept
{
    std::free(p);
}
void operator delete[](void* p) noexcept
{
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept
{
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept
{
    std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept
{
    std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept
{
    std::free(p);
}
