#include "radiosity/geometry_cache.h"

#include <cstring>
#include <list>
#include <mutex>
#include <vector>

namespace metamer::radiosity {

namespace {

// The inputs as bytes: what a hit must match exactly.
class Key {
public:
    template <typename T>
    void add(std::span<const T> values) {
        const size_t size = values.size();
        append(&size, sizeof size);
        if (size) append(values.data(), values.size_bytes());
    }
    void addOccluders(const Bvh& bvh) {
        for (const BvhTriangle& t : bvh.triangles()) {
            append(&t.p0, sizeof t.p0);
            append(&t.p1, sizeof t.p1);
            append(&t.p2, sizeof t.p2);
            append(&t.mesh, sizeof t.mesh);
        }
    }
    bool operator==(const Key& other) const { return hash_ == other.hash_ && bytes_ == other.bytes_; }

private:
    void append(const void* data, size_t size) {
        const auto* p = static_cast<const unsigned char*>(data);
        bytes_.insert(bytes_.end(), p, p + size);
        for (size_t i = 0; i < size; ++i) hash_ = (hash_ ^ p[i]) * 1099511628211ull;  // FNV-1a
    }
    std::vector<unsigned char> bytes_;
    uint64_t hash_ = 14695981039346656037ull;
};

template <typename Value>
class Kept {
public:
    // The value kept under `key`, else make()'s, kept as the most recent.
    template <typename Make>
    std::shared_ptr<const Value> get(Key key, Make make, bool& hit) {
        {
            std::lock_guard lock(mutex_);
            for (auto it = entries_.begin(); it != entries_.end(); ++it)
                if (it->first == key) {
                    entries_.splice(entries_.begin(), entries_, it);
                    hit = true;
                    return entries_.front().second;
                }
        }
        hit = false;
        auto value = std::make_shared<const Value>(make());
        std::lock_guard lock(mutex_);
        entries_.emplace_front(std::move(key), value);
        while (entries_.size() > kGeometryCacheEntries) entries_.pop_back();
        return value;
    }
    void clear() {
        std::lock_guard lock(mutex_);
        entries_.clear();
    }

private:
    std::mutex mutex_;
    std::list<std::pair<Key, std::shared_ptr<const Value>>> entries_;
};

Kept<Coupling>& formFactors() {
    static Kept<Coupling> kept;
    return kept;
}

// The vertices' factors (centroid visibility) and the emitters' (sampled) each keep their own
// most recent entries: one render makes one of each.
Kept<Eigen::MatrixXd>& gathers(int side) {
    static Kept<Eigen::MatrixXd> centroid, sampled;
    return side == 0 ? centroid : sampled;
}

struct Last {
    std::mutex mutex;
    std::weak_ptr<const Coupling> factors;
    LastSolve solve;
};

Last& last() {
    static Last kept;
    return kept;
}

}  // namespace

std::optional<LastSolve> lastSolveOn(const Coupling& factors) {
    Last& l = last();
    std::lock_guard lock(l.mutex);
    const std::shared_ptr<const Coupling> held = l.factors.lock();
    if (held.get() != &factors) return std::nullopt;
    return l.solve;
}

void keepLastSolve(const std::shared_ptr<const Coupling>& factors, LastSolve solve) {
    Last& l = last();
    std::lock_guard lock(l.mutex);
    l.factors = factors;
    l.solve = std::move(solve);
    l.solve.problem.formFactors.resize(0, 0);
    l.solve.problem.sharedFormFactors.reset();  // held weakly, as `factors`
}

std::shared_ptr<const Coupling> cachedFormFactors(std::span<const std::array<glm::dvec3, 3>> elements, const Bvh& occluders,
                                                  std::span<const uint32_t> source, bool& hit) {
    Key key;
    key.add(elements);
    key.add(source);
    key.addOccluders(occluders);
    return formFactors().get(std::move(key), [&] { return formFactorMatrix(elements, &occluders, source); }, hit);
}

std::shared_ptr<const Eigen::MatrixXd> cachedGatherFactors(std::span<const GatherPoint> points,
                                                           std::span<const std::array<glm::dvec3, 3>> elements,
                                                           const Bvh& occluders, int side, bool& hit) {
    Key key;
    for (const GatherPoint& p : points) {  // field by field: the struct has padding
        key.add(std::span<const glm::dvec3>({p.position, p.normal, p.inside}));
        key.add(std::span<const uint32_t>(&p.source, 1));
    }
    key.add(elements);
    key.add(std::span<const int>(&side, 1));
    key.addOccluders(occluders);
    return gathers(side).get(std::move(key), [&] { return gatherFactors(points, elements, &occluders, side); }, hit);
}

void clearGeometryCache() {
    formFactors().clear();
    gathers(0).clear();
    gathers(1).clear();
    std::lock_guard lock(last().mutex);
    last().factors.reset();
    last().solve = {};
}

}  // namespace metamer::radiosity
