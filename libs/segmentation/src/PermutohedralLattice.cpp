#include "smap/segmentation/PermutohedralLattice.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>

namespace smap::segmentation
{
namespace
{
/// a[0..n) == b[0..n) (inlined: tiny arrays, where a memcmp call costs more than the work).
inline bool sameInts(const int* a, const int* b, int n)
{
    for (int i = 0; i < n; i++)
        if (a[i] != b[i])
            return false;
    return true;
}

/// Open-addressing hash table from d-integer lattice keys to dense vertex ids. When every
/// coordinate fits in 12 bits and d <= 5 (images: always), keys are also packed into one
/// 64-bit word, which makes hashing and comparing one operation each.
class KeyTable
{
public:
    static constexpr int kPackBits = 12;
    static constexpr int kPackLimit = 1 << (kPackBits - 1);  ///< |coordinate| < this

    KeyTable(int d, size_t expected, bool packed) : d_(d), packed_(packed)
    {
        size_t cap = 64;
        while (cap < 2 * expected)
            cap *= 2;
        slots_.assign(cap, -1);
        mask_ = cap - 1;
        if (packed_)
            packedKeys_.reserve(expected);
        else
            keys_.reserve(expected * static_cast<size_t>(d));
    }

    /// The id of `key`, inserting it when absent.
    int insert(const int* key)
    {
        if (packed_)
            return insertPacked(pack(key));
        const size_t h = probe(key);
        if (slots_[h] >= 0)
            return slots_[h];
        keys_.insert(keys_.end(), key, key + d_);
        return occupy(h);
    }
    int insertPacked(uint64_t p)
    {
        const size_t h = probePacked(p);
        if (slots_[h] >= 0)
            return slots_[h];
        packedKeys_.push_back(p);
        return occupy(h);
    }
    /// The id of `key`, or -1 (read-only: safe from several threads).
    int lookup(const int* key) const
    {
        return packed_ ? lookupPacked(pack(key)) : slots_[probe(key)];
    }
    int lookupPacked(uint64_t p) const { return slots_[probePacked(p)]; }

    bool packed() const { return packed_; }
    uint64_t packedKey(int id) const { return packedKeys_[static_cast<size_t>(id)]; }
    /// The packed form of an offset: adding it to a packed key adds `delta` coordinate-wise
    /// (no field leaves its range, by the packing condition, so nothing carries across).
    uint64_t packedOffset(const int* delta) const
    {
        uint64_t p = 0;
        for (int k = 0; k < d_; k++)
            p += static_cast<uint64_t>(static_cast<int64_t>(delta[k]) << (kPackBits * k));
        return p;
    }
    uint64_t pack(const int* key) const
    {
        uint64_t p = 0;
        for (int k = 0; k < d_; k++)
            p |= static_cast<uint64_t>(key[k] + kPackLimit) << (kPackBits * k);
        return p;
    }

    int size() const
    {
        return packed_ ? static_cast<int>(packedKeys_.size())
                       : static_cast<int>(keys_.size() / static_cast<size_t>(d_));
    }
    const int* key(int id) const { return keys_.data() + static_cast<size_t>(id) * d_; }

private:
    /// The slot holding `key`, or the empty slot where it would go.
    size_t probe(const int* key) const
    {
        size_t h = hash(key) & mask_;
        while (slots_[h] >= 0 &&
               !sameInts(key, keys_.data() + static_cast<size_t>(slots_[h]) * d_, d_))
            h = (h + 1) & mask_;
        return h;
    }
    size_t probePacked(uint64_t p) const
    {
        size_t h = hashPacked(p) & mask_;
        while (slots_[h] >= 0 && packedKeys_[static_cast<size_t>(slots_[h])] != p)
            h = (h + 1) & mask_;
        return h;
    }
    /// Gives the newest key (already appended) the id size() - 1 at empty slot h.
    int occupy(size_t h)
    {
        const int fresh = size() - 1;
        slots_[h] = fresh;
        if (2 * static_cast<size_t>(fresh + 1) > slots_.size())
            grow();
        return fresh;
    }
    static size_t hashPacked(uint64_t p)
    {
        const uint64_t h = p * 0x9E3779B97F4A7C15ull;
        return static_cast<size_t>(h ^ (h >> 32));
    }
    size_t hash(const int* key) const
    {
        uint64_t h = 1469598103934665603ull;
        for (int k = 0; k < d_; k++)
            h = (h ^ static_cast<uint32_t>(key[k])) * 1099511628211ull;
        return static_cast<size_t>(h ^ (h >> 29));
    }
    size_t slotHash(int id) const
    {
        return packed_ ? hashPacked(packedKeys_[static_cast<size_t>(id)]) : hash(key(id));
    }

    void grow()
    {
        slots_.assign(slots_.size() * 2, -1);
        mask_ = slots_.size() - 1;
        for (int id = 0; id < size(); id++)
        {
            size_t h = slotHash(id) & mask_;
            while (slots_[h] >= 0)
                h = (h + 1) & mask_;
            slots_[h] = id;
        }
    }

    int d_;
    bool packed_;
    size_t mask_ = 0;
    std::vector<int> slots_;
    std::vector<int> keys_;
    std::vector<uint64_t> packedKeys_;
};

/// Point p's enclosing simplex: its remainder-0 corner and ranks (which fix the d+1 vertices)
/// and barycentric weights. `scale` holds the embedding's per-dimension factors; the buffers
/// have d+1 (+1) entries.
void enclosingSimplex(const float* f, int d, const double* scale, int* rem0, int* rank,
                      float* weights, double* elevated, double* bary)
{
    const int d1 = d + 1;
    const double invD1 = 1.0 / d1;
    double sum = 0.0;
    for (int i = d; i >= 1; i--)
    {
        const double c = f[i - 1] * scale[i - 1];
        elevated[i] = sum - i * c;
        sum += c;
    }
    elevated[0] = sum;

    // Nearest point whose coordinates are all multiples of d+1, then the ranks of the
    // differences (0 = largest).
    int remSum = 0;
    double diff[PermutohedralLattice::kMaxDimensions + 1];
    for (int j = 0; j < d1; j++)
    {
        const int r = static_cast<int>(std::floor(elevated[j] * invD1 + 0.5));
        rem0[j] = r * d1;
        remSum += r;
        rank[j] = 0;
        diff[j] = elevated[j] - rem0[j];
    }
    for (int j = 0; j < d1; j++)
    {
        for (int k = j + 1; k < d1; k++)
        {
            const int jSmaller = diff[j] < diff[k] ? 1 : 0;  // branch-free: data-dependent
            rank[j] += jSmaller;
            rank[k] += 1 - jSmaller;
        }
    }
    // That point must lie on the hyperplane too: move the coordinates rounded furthest.
    for (int j = 0; j < d1; j++)
    {
        if (remSum > 0 && rank[j] >= d1 - remSum)
        {
            rem0[j] -= d1;
            rank[j] += remSum - d1;
        }
        else if (remSum < 0 && rank[j] < -remSum)
        {
            rem0[j] += d1;
            rank[j] += d1 + remSum;
        }
        else
        {
            rank[j] += remSum;
        }
    }

    // Barycentric coordinates in the simplex.
    std::fill(bary, bary + d1 + 1, 0.0);
    for (int j = 0; j < d1; j++)
    {
        const double delta = (elevated[j] - rem0[j]) * invD1;
        bary[d - rank[j]] += delta;
        bary[d1 - rank[j]] -= delta;
    }
    bary[0] += 1.0 + bary[d1];

    for (int r = 0; r < d1; r++)
        weights[r] = static_cast<float>(bary[r]);
}
/// Embedding into the hyperplane sum(x) = 0 of R^(d+1) with the orthonormal basis
/// u_i = (1, ..., 1, -i, 0, ..., 0) / sqrt(i (i+1)) (i ones), scaled so that the lattice blur
/// approximates a unit Gaussian: sqrt(2/3) (d+1) (Adams et al., section 3).
std::vector<double> embeddingScales(int d)
{
    std::vector<double> scale(static_cast<size_t>(d));
    const double invStd = std::sqrt(2.0 / 3.0) * (d + 1);
    for (int i = 1; i <= d; i++)
        scale[static_cast<size_t>(i - 1)] = invStd / std::sqrt(static_cast<double>(i) * (i + 1));
    return scale;
}

/// The enclosing simplex of every point (rows of `features`), in parallel.
void computeSimplices(const cv::Mat& features, const std::vector<double>& scale,
                      std::vector<int>& rem0, std::vector<int>& rank, std::vector<float>& weights)
{
    const int n = features.rows, d = features.cols, d1 = d + 1;
    rem0.resize(static_cast<size_t>(n) * d1);
    rank.resize(static_cast<size_t>(n) * d1);
    weights.resize(static_cast<size_t>(n) * d1);
    cv::parallel_for_(cv::Range(0, n),
                      [&](const cv::Range& range)
                      {
                          double elevated[PermutohedralLattice::kMaxDimensions + 1];
                          double bary[PermutohedralLattice::kMaxDimensions + 2];
                          for (int p = range.start; p < range.end; p++)
                          {
                              const size_t at = static_cast<size_t>(p) * d1;
                              enclosingSimplex(features.ptr<float>(p), d, scale.data(),
                                               rem0.data() + at, rank.data() + at,
                                               weights.data() + at, elevated, bary);
                          }
                      });
}

/// Whether every vertex key (and its neighbours') fits the packed 64-bit form: vertex
/// coordinates stay within rem0 +- (d+1), neighbours' within +- 2 (d+1) more.
bool keysPackable(const std::vector<int>& rem0, int d)
{
    int largest = 0;
    for (const int r : rem0)
        largest = std::max(largest, std::abs(r));
    return d * KeyTable::kPackBits <= 64 && largest + 3 * (d + 1) < KeyTable::kPackLimit;
}

/// The vertices of stripe `st`'s points hashed into its own table (ids local to the stripe).
void hashStripe(int st, int stripes, int n, int d, const std::vector<int>& rem0,
                const std::vector<int>& rank, KeyTable& table, std::vector<int>& vertexOfPoint)
{
    const int d1 = d + 1;
    std::vector<int> key(static_cast<size_t>(d));
    const int begin = static_cast<int>(static_cast<int64_t>(n) * st / stripes);
    const int end = static_cast<int>(static_cast<int64_t>(n) * (st + 1) / stripes);
    for (int p = begin; p < end; p++)
    {
        const size_t at = static_cast<size_t>(p) * d1;
        const int* r0 = rem0.data() + at;
        const int* rk = rank.data() + at;
        int* v = vertexOfPoint.data() + at;
        // Neighbouring pixels often share a simplex: reuse the previous point's.
        if (p > begin && sameInts(r0, r0 - d1, d1) && sameInts(rk, rk - d1, d1))
        {
            std::copy(v - d1, v, v);
            continue;
        }
        // Vertex r: the remainder-0 corner plus the canonical simplex's vertex r.
        for (int r = 0; r < d1; r++)
        {
            for (int j = 0; j < d; j++)
                key[static_cast<size_t>(j)] = r0[j] + (rk[j] > d - r ? r - d1 : r);
            v[r] = table.insert(key.data());
        }
    }
}

/// The stripes' tables merged into the first in stripe order (so ids depend on the stripe
/// count only), `vertexOfPoint` renumbered to the merged ids.
void mergeStripes(std::vector<KeyTable>& tables, bool packable, int n, int d1,
                  std::vector<int>& vertexOfPoint)
{
    const int stripes = static_cast<int>(tables.size());
    KeyTable& table = tables[0];
    for (int st = 1; st < stripes; st++)
    {
        const KeyTable& local = tables[static_cast<size_t>(st)];
        std::vector<int> global(static_cast<size_t>(local.size()));
        for (int id = 0; id < local.size(); id++)
            global[static_cast<size_t>(id)] =
                packable ? table.insertPacked(local.packedKey(id)) : table.insert(local.key(id));
        const size_t begin = static_cast<size_t>(static_cast<int64_t>(n) * st / stripes) * d1;
        const size_t end = static_cast<size_t>(static_cast<int64_t>(n) * (st + 1) / stripes) * d1;
        for (size_t slot = begin; slot < end; slot++)
            vertexOfPoint[slot] = global[static_cast<size_t>(vertexOfPoint[slot])];
    }
}

/// Neighbours of every vertex along each lattice axis j: +-(1, ..., 1, -d, 1, ..., 1) (-d at j),
/// -1 where the lattice has no such vertex; (v * (d+1) + j) * 2 + (0: minus, 1: plus).
std::vector<int> findNeighbours(const KeyTable& table, int d, bool packable, int stripes)
{
    const int d1 = d + 1, m = table.size();
    std::vector<int> neighbours(static_cast<size_t>(m) * d1 * 2, -1);
    auto offset = [d](int i, int j, int sgn) { return (sgn == 0 ? -1 : 1) * (i == j ? -d : 1); };
    std::vector<uint64_t> step(static_cast<size_t>(d1) * 2);
    if (packable)
    {
        std::vector<int> nb(static_cast<size_t>(d));
        for (int j = 0; j < d1; j++)
        {
            for (int sgn = 0; sgn < 2; sgn++)
            {
                for (int i = 0; i < d; i++)
                    nb[static_cast<size_t>(i)] = offset(i, j, sgn);
                step[static_cast<size_t>(j) * 2 + sgn] = table.packedOffset(nb.data());
            }
        }
    }
    cv::parallel_for_(
        cv::Range(0, m),
        [&](const cv::Range& range)
        {
            std::vector<int> nbKey(static_cast<size_t>(d));
            for (int v = range.start; v < range.end; v++)
            {
                for (int j = 0; j < d1; j++)
                {
                    for (int sgn = 0; sgn < 2; sgn++)
                    {
                        int& out = neighbours[(static_cast<size_t>(v) * d1 + j) * 2 + sgn];
                        if (packable)
                        {
                            out = table.lookupPacked(table.packedKey(v) +
                                                     step[static_cast<size_t>(j) * 2 + sgn]);
                            continue;
                        }
                        const int* k = table.key(v);
                        for (int i = 0; i < d; i++)
                            nbKey[static_cast<size_t>(i)] = k[i] + offset(i, j, sgn);
                        out = table.lookup(nbKey.data());
                    }
                }
            }
        },
        stripes);
    return neighbours;
}
}  // namespace

PermutohedralLattice::PermutohedralLattice(const cv::Mat& features)
{
    build(features);
}

void PermutohedralLattice::build(const cv::Mat& features)
{
    CV_Assert(features.type() == CV_32FC1 && features.cols >= 1 &&
              features.cols <= kMaxDimensions && features.rows > 0);
    d_ = features.cols;
    n_ = features.rows;
    const int d1 = d_ + 1;
    // Simplices of all points in parallel, then their vertices hashed. The buffers keep their
    // capacity from build to build.
    computeSimplices(features, embeddingScales(d_), rem0_, rank_, weightOfPoint_);
    // Images have far fewer vertices than points (about 1 in 7 at 320x240); the tables grow.
    const bool packable = keysPackable(rem0_, d_);
    // Stripes of points are hashed in parallel, each into its own table, then merged.
    const int stripes = std::max(1, std::min(cv::getNumThreads(), 8));
    std::vector<KeyTable> tables;
    tables.reserve(static_cast<size_t>(stripes));
    for (int st = 0; st < stripes; st++)
        tables.emplace_back(d_, static_cast<size_t>(n_) / (8 * stripes), packable);
    vertexOfPoint_.resize(static_cast<size_t>(n_) * d1);
    cv::parallel_for_(
        cv::Range(0, stripes),
        [&](const cv::Range& range)
        {
            for (int st = range.start; st < range.end; st++)
                hashStripe(st, stripes, n_, d_, rem0_, rank_, tables[static_cast<size_t>(st)],
                           vertexOfPoint_);
        },
        stripes);
    mergeStripes(tables, packable, n_, d1, vertexOfPoint_);
    vertexCount_ = tables[0].size();
    neighbours_ = findNeighbours(tables[0], d_, packable, stripes);
}

namespace
{
// The hot loops, compiled for AVX2 too and picked at run time (GCC function multiversioning):
// the channel loops vectorise, in blocks of 8 (callers pad channels to a multiple of 8).

/// dst += w src over c channels.
inline void axpy(float* __restrict dst, const float* __restrict src, float w, int c)
{
    int k = 0;
    for (; k + 8 <= c; k += 8)
        for (int j = 0; j < 8; j++)
            dst[k + j] += w * src[k + j];
    for (; k < c; k++)
        dst[k] += w * src[k];
}

/// acc[vertex] += w * in[point] over the simplices of points [begin, end).
__attribute__((target_clones("avx2", "default"))) void splatPoints(
    const float* in, const float* inScale, int c, int begin, int end, int d1,
    const int* vertexOfPoint, const float* weightOfPoint, float* acc)
{
    for (int p = begin; p < end; p++)
    {
        const float* __restrict src = in + static_cast<size_t>(p) * c;
        const float scale = inScale ? inScale[p] : 1.0f;
        for (int r = 0; r < d1; r++)
        {
            const size_t slot = static_cast<size_t>(p) * d1 + r;
            const float w = weightOfPoint[slot] * scale;
            axpy(acc + static_cast<size_t>(vertexOfPoint[slot]) * c, src, w, c);
        }
    }
}

/// One blur pass along an axis: dst[v] = src[v] + (src[n1] + src[n2]) / 2, one pass over
/// the channels; a missing neighbour reads `zeros` (c zeros).
__attribute__((target_clones("avx2", "default"))) void blurVertices(const float* src, float* dst,
                                                                    const float* zeros, int c,
                                                                    int begin, int end, int d1,
                                                                    int axis, const int* neighbours)
{
    for (int v = begin; v < end; v++)
    {
        const int* nb = neighbours + (static_cast<size_t>(v) * d1 + axis) * 2;
        const float* __restrict self = src + static_cast<size_t>(v) * c;
        const float* __restrict a = nb[0] < 0 ? zeros : src + static_cast<size_t>(nb[0]) * c;
        const float* __restrict b = nb[1] < 0 ? zeros : src + static_cast<size_t>(nb[1]) * c;
        float* __restrict out = dst + static_cast<size_t>(v) * c;
        int k = 0;
        for (; k + 8 <= c; k += 8)
            for (int j = 0; j < 8; j++)
                out[k + j] = self[k + j] + 0.5f * (a[k + j] + b[k + j]);
        for (; k < c; k++)
            out[k] = self[k] + 0.5f * (a[k] + b[k]);
    }
}

/// out[point] = s_p sum_r w_r values[vertex_r] for points [begin, end).
__attribute__((target_clones("avx2", "default"))) void slicePoints(
    const float* values, const float* outScale, float outWeight, int c, int begin, int end, int d1,
    const int* vertexOfPoint, const float* weightOfPoint, float* out)
{
    for (int p = begin; p < end; p++)
    {
        float* __restrict dst = out + static_cast<size_t>(p) * c;
        for (int k = 0; k < c; k++)
            dst[k] = 0.0f;
        const float scale = outWeight * (outScale ? outScale[p] : 1.0f);
        for (int r = 0; r < d1; r++)
        {
            const size_t slot = static_cast<size_t>(p) * d1 + r;
            const float w = weightOfPoint[slot] * scale;
            axpy(dst, values + static_cast<size_t>(vertexOfPoint[slot]) * c, w, c);
        }
    }
}
}  // namespace

void PermutohedralLattice::splatAndBlur(const cv::Mat& in, cv::Mat& values, const float* inScale,
                                        std::vector<cv::Mat>* scratch) const
{
    CV_Assert(in.type() == CV_32FC1 && in.rows == n_ && in.isContinuous());
    const int c = in.cols, d1 = d_ + 1, m = vertexCount();

    // Splat: each stripe of points scatters into its own copy of the (small, cache-resident)
    // vertex array; the copies are summed. Buffers: the caller's scratch (reused) or fresh.
    const int stripes = std::max(1, std::min(cv::getNumThreads(), 8));
    std::vector<cv::Mat> local;
    std::vector<cv::Mat>& buffers = scratch ? *scratch : local;
    buffers.resize(static_cast<size_t>(stripes) + 1);
    cv::parallel_for_(
        cv::Range(0, stripes),
        [&](const cv::Range& range)
        {
            for (int st = range.start; st < range.end; st++)
            {
                cv::Mat& acc = buffers[static_cast<size_t>(st)];
                acc.create(m, c, CV_32FC1);
                acc.setTo(0.0f);
                const int begin = static_cast<int>(static_cast<int64_t>(n_) * st / stripes);
                const int end = static_cast<int>(static_cast<int64_t>(n_) * (st + 1) / stripes);
                splatPoints(in.ptr<float>(), inScale, c, begin, end, d1, vertexOfPoint_.data(),
                            weightOfPoint_.data(), acc.ptr<float>());
            }
        },
        stripes);
    cv::Mat sum = buffers[0];
    for (int st = 1; st < stripes; st++)
        sum += buffers[static_cast<size_t>(st)];

    cv::Mat blurred = buffers[static_cast<size_t>(stripes)];
    blurred.create(m, c, CV_32FC1);
    buffers[static_cast<size_t>(stripes)] = blurred;
    values = sum;
    const std::vector<float> zeros(static_cast<size_t>(c), 0.0f);
    for (int j = 0; j < d1; j++)
    {
        cv::parallel_for_(
            cv::Range(0, m),
            [&](const cv::Range& range)
            {
                blurVertices(values.ptr<float>(), blurred.ptr<float>(), zeros.data(), c,
                             range.start, range.end, d1, j, neighbours_.data());
            },
            stripes);
        std::swap(values, blurred);
    }
}

void PermutohedralLattice::filter(const cv::Mat& in, cv::Mat& out, const float* inScale,
                                  const float* outScale, float outWeight) const
{
    cv::Mat values;
    splatAndBlur(in, values, inScale);
    out.create(n_, in.cols, CV_32FC1);
    const int stripes = std::max(1, std::min(cv::getNumThreads(), 8));
    cv::parallel_for_(
        cv::Range(0, n_),
        [&](const cv::Range& range)
        {
            slicePoints(values.ptr<float>(), outScale, outWeight, in.cols, range.start, range.end,
                        d_ + 1, vertexOfPoint_.data(), weightOfPoint_.data(), out.ptr<float>());
        },
        stripes);
}
}  // namespace smap::segmentation
