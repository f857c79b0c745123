#include "app/cli/bench/bench_json.h"

#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <set>
#include <tuple>
#include <type_traits>
#include <utility>

#include "engine/render/answers.h"
#include "engine/render/answers_json.h"
#include "visibility/fp_query/work_budget.h"

namespace penumbra::cli {
namespace {

using nlohmann::json;

// ---- Field kinds: how one member of a struct S sits in S's JSON object ---------------------

// A value under `key`.
template <class S, class T>
struct Field {
    const char* key;
    T S::*member;
};
// A value under `key`, the key absent when the optional is empty.
template <class S, class T>
struct OptionalField {
    const char* key;
    std::optional<T> S::*member;
};
// A number under `key`, null when it is not finite (a quantity the study could not estimate).
template <class S>
struct NumberOrNull {
    const char* key;
    double S::*member;
};
// A struct's keys in S's own object.
template <class S, class T>
struct Inline {
    T S::*member;
};
// The same when the optional holds one; read back when S's object has `marker` (a key of T).
template <class S, class T>
struct InlineIf {
    const char* marker;
    std::optional<T> S::*member;
};
// Counts indexed by the enum E, as an object keyed by E's names (toString).
template <class S, class E, size_t N>
struct Named {
    const char* key;
    std::array<uint64_t, N> S::*member;
};
// Answer counts, written by the tree's one writer of them (engine/render/answers_json.h).
template <class S>
struct AnswerCounts {
    const char* key;
    std::array<uint64_t, kAnswers> S::*member;
};
// One element of an array member, under its own key.
template <class S, class T, size_t N>
struct Element {
    const char* key;
    T (S::*member)[N];
    size_t index;
};
// The size of a vector member (read back: it must match the vector, read before it).
template <class S, class T>
struct Count {
    const char* key;
    std::vector<T> S::*member;
};

template <class S, class T>
Field<S, T> field(const char* key, T S::*member) {
    return {key, member};
}
template <class S, class T>
OptionalField<S, T> optional(const char* key, std::optional<T> S::*member) {
    return {key, member};
}
template <class S, class T>
Inline<S, T> inlined(T S::*member) {
    return {member};
}
template <class S, class T>
InlineIf<S, T> inlinedIf(const char* marker, std::optional<T> S::*member) {
    return {marker, member};
}
template <class E, class S, size_t N>
Named<S, E, N> named(const char* key, std::array<uint64_t, N> S::*member) {
    return {key, member};
}
template <class S, class T, size_t N>
Element<S, T, N> element(const char* key, T (S::*member)[N], size_t index) {
    return {key, member, index};
}

// ---- The schema: each struct's keys, once ---------------------------------------------------

template <class T>
struct Schema;

template <class T>
concept HasSchema = requires {
    Schema<T>::fields();
};

template <>
struct Schema<BenchMachine> {
    using S = BenchMachine;
    static auto fields() {
        return std::tuple{field("cpu", &S::cpu), field("cores", &S::cores),
                          field("loadavg", &S::loadavg), field("date", &S::date),
                          field("buildType", &S::buildType)};
    }
};

template <>
struct Schema<BenchSettings> {
    using S = BenchSettings;
    static auto fields() {
        return std::tuple{field("size", &S::size),
                          field("largeSize", &S::largeSize),
                          field("spp", &S::spp),
                          field("quick", &S::quick),
                          field("skipLarge", &S::skipLarge),
                          field("limit", &S::limit),
                          field("exactCostSize", &S::exactCostSize)};
    }
};

template <>
struct Schema<SkippedScene> {
    using S = SkippedScene;
    static auto fields() {
        return std::tuple{field("study", &S::study), field("scene", &S::scene),
                          field("missing", &S::missing)};
    }
};

template <>
struct Schema<PairKinds> {
    using S = PairKinds;
    static auto fields() {
        return std::tuple{field("backFacing", &S::backFacing),
                          field("fullyVisible", &S::fullyVisible),
                          field("fullyHidden", &S::fullyHidden), field("penumbra", &S::penumbra),
                          field("partial", &S::partial)};
    }
};

template <>
struct Schema<PrecomputeRun> {
    using S = PrecomputeRun;
    static auto fields() {
        return std::tuple{field("seconds", &S::seconds),   field("cpu", &S::cpu),
                          field("pairs", &S::pairs),       field("done", &S::done),
                          field("complete", &S::complete), field("trees", &S::trees),
                          field("nodes", &S::nodes),       field("bytes", &S::bytes),
                          field("kinds", &S::kinds)};
    }
};

// ---- Table 1

template <>
struct Schema<SampledRender> {
    using S = SampledRender;
    static auto fields() {
        return std::tuple{field("wall", &S::wall),
                          field("cpu", &S::cpu),
                          field("points", &S::points),
                          field("pointMedianUs", &S::pointMedianUs),
                          field("pointP99Us", &S::pointP99Us),
                          field("pointMeanUs", &S::pointMeanUs),
                          field("pointQuantileStride", &S::pointQuantileStride)};
    }
};

template <>
struct Schema<EvaluationTimes> {
    using S = EvaluationTimes;
    static auto fields() {
        return std::tuple{field("evaluations", &S::evaluations),
                          field("medianUs", &S::medianUs),
                          field("p99Us", &S::p99Us),
                          field("meanUs", &S::meanUs),
                          field("quantileStride", &S::quantileStride),
                          field("chainEvaluations", &S::chainEvaluations),
                          field("chainEdges", &S::chainEdges),
                          field("chainCells", &S::chainCells),
                          field("chainFragments", &S::chainFragments)};
    }
};

template <>
struct Schema<TimeSplit> {
    using S = TimeSplit;
    static auto fields() {
        return std::tuple{field("exactSeconds", &S::exactSeconds),
                          field("attemptSeconds", &S::attemptSeconds),
                          field("raysSeconds", &S::raysSeconds)};
    }
};

template <>
struct Schema<LightEdgeCounts> {
    using S = LightEdgeCounts;
    static auto fields() {
        return std::tuple{field("evaluations", &S::evaluations), field("examined", &S::examined),
                          field("weighted", &S::weighted), field("inCone", &S::inCone)};
    }
};

template <>
struct Schema<ExactCost> {
    using S = ExactCost;
    static auto fields() {
        return std::tuple{inlined(&S::times),
                          field("sampledMedianUs", &S::sampledMedianUs),
                          field("sampledQuantileStride", &S::sampledQuantileStride),
                          field("chainOccluderEdges", &S::chainOccluderEdges),
                          field("timeSplit", &S::timeSplit),
                          optional("lightEdges", &S::lightEdges)};
    }
};

template <>
struct Schema<EveryPointExactCost> {
    using S = EveryPointExactCost;
    static auto fields() {
        return std::tuple{inlined(&S::times),          field("width", &S::width),
                          field("height", &S::height), field("spp", &S::spp),
                          field("image", &S::image),   field("complete", &S::complete)};
    }
};

template <>
struct Schema<WorkByPath> {
    using S = WorkByPath;
    static auto fields() {
        return std::tuple{named<vis::WorkStage>("trees", &S::trees),
                          named<vis::WorkStage>("direct", &S::direct)};
    }
};

template <>
struct Schema<EveryPointExactRender> {
    using S = EveryPointExactRender;
    static auto fields() {
        return std::tuple{field("complete", &S::complete), field("renderWall", &S::renderWall),
                          field("renderCpu", &S::renderCpu), optional("workAt", &S::workAt)};
    }
};

template <>
struct Schema<Refinement> {
    using S = Refinement;
    static auto fields() {
        return std::tuple{field("pairs", &S::pairs), field("trees", &S::trees),
                          field("treesUsed", &S::treesUsed), field("notWorth", &S::notWorth),
                          field("seconds", &S::seconds)};
    }
};

template <>
struct Schema<AnswersImage> {
    using S = AnswersImage;
    static auto fields() {
        return std::tuple{field("image", &S::image), AnswerCounts<S>{"counts", &S::counts}};
    }
};

template <>
struct Schema<ExactRender> {
    using S = ExactRender;
    static auto fields() {
        return std::tuple{
            field("answers", &S::answers),
            field("renderWall", &S::renderWall),
            field("renderCpu", &S::renderCpu),
            field("wall", &S::wall),
            field("cpu", &S::cpu),
            field("pairsWithoutTree", &S::pairsWithoutTree),
            field("pairsGroupedNoTree", &S::pairsGroupedNoTree),
            field("directEvaluations", &S::directEvaluations),
            field("directGroupedEvaluations", &S::directGroupedEvaluations),
            field("directSolidEvaluations", &S::directSolidEvaluations),
            field("directHiddenBySolidEvaluations", &S::directHiddenBySolidEvaluations),
            field("partialByGroupsEvaluations", &S::partialByGroupsEvaluations),
            field("evaluations", &S::evaluations),
            field("sampledEvaluations", &S::sampledEvaluations),
            named<vis::WorkStage>("overLimitAt", &S::overLimitAt),
            field("notTried", &S::notTried),
            field("workAt", &S::workAt),
            field("cost", &S::cost),
            field("exactWorkLimit", &S::exactWorkLimit),
            field("minTreeSamples", &S::minTreeSamples),
            field("refined", &S::refined),
            optional("everyPointExact", &S::everyPointExact),
            optional("costEveryPointExact", &S::costEveryPointExact)};
    }
};

template <>
struct Schema<ExactRun> {
    using S = ExactRun;
    static auto fields() {
        return std::tuple{field("precomputeWall", &S::precomputeWall),
                          field("precomputeCpu", &S::precomputeCpu),
                          field("precomputeComplete", &S::precomputeComplete),
                          field("trees", &S::trees),
                          field("nodes", &S::nodes),
                          field("bytes", &S::bytes),
                          field("kinds", &S::kinds),
                          field("fileBytes", &S::fileBytes),
                          inlinedIf("renderWall", &S::render)};
    }
};

template <>
struct Schema<Speedups> {
    using S = Speedups;
    static auto fields() {
        return std::tuple{field("speedupWall", &S::wall), field("speedupCpu", &S::cpu),
                          field("speedupRenderOnlyWall", &S::renderOnlyWall),
                          field("speedupRenderOnlyCpu", &S::renderOnlyCpu)};
    }
};

template <>
struct Schema<AllPairsRun> {
    using S = AllPairsRun;
    static auto fields() {
        return std::tuple{inlined(&S::precompute), field("fileBytes", &S::fileBytes)};
    }
};

template <>
struct Schema<ShadowEdges> {
    using S = ShadowEdges;
    static auto fields() {
        return std::tuple{field("edges", &S::edges),
                          field("open", &S::open),
                          field("keptOverLights", &S::keptOverLights),
                          field("minShare", &S::minShare),
                          field("maxShare", &S::maxShare),
                          field("seconds", &S::seconds)};
    }
};

template <>
struct Schema<EqualErrorSample> {
    using S = EqualErrorSample;
    static auto fields() {
        return std::tuple{field("rays", &S::rays), field("wall", &S::wall), field("cpu", &S::cpu),
                          field("relativeRmse", &S::relativeRmse)};
    }
};

template <>
struct Schema<EqualErrorFound> {
    using S = EqualErrorFound;
    static auto fields() {
        return std::tuple{field("rays", &S::rays),
                          field("wall", &S::wall),
                          field("cpu", &S::cpu),
                          field("relativeRmse", &S::relativeRmse),
                          field("speedupWall", &S::speedupWall),
                          field("speedupCpu", &S::speedupCpu)};
    }
};

template <>
struct Schema<EqualErrorRun> {
    using S = EqualErrorRun;
    static auto fields() {
        return std::tuple{field("target", &S::target),
                          field("maxRays", &S::maxRays),
                          field("exactComplete", &S::exactComplete),
                          field("exactWall", &S::exactWall),
                          field("exactCpu", &S::exactCpu),
                          field("exactPrecomputeWall", &S::exactPrecomputeWall),
                          field("pixels", &S::pixels),
                          field("penumbraPixels", &S::penumbraPixels),
                          field("penumbraMeanRadiance", &S::penumbraMeanRadiance),
                          field("searched", &S::searched),
                          optional("found", &S::found),
                          field("why", &S::why)};
    }
};

template <>
struct Schema<Table1Row> {
    using S = Table1Row;
    static auto fields() {
        return std::tuple{field("scene", &S::scene),
                          field("faces", &S::faces),
                          field("areaLights", &S::areaLights),
                          optional("shadowEdges", &S::shadowEdges),
                          field("width", &S::width),
                          field("height", &S::height),
                          field("spp", &S::spp),
                          field("sampled128", &S::sampled128),
                          field("exact", &S::exact),
                          inlinedIf("speedupWall", &S::speedup),
                          optional("allPairs", &S::allPairs),
                          optional("equalError", &S::equalError)};
    }
};

// ---- The other studies

template <>
struct Schema<AccuracyPoint> {
    using S = AccuracyPoint;
    static auto fields() {
        return std::tuple{field("method", &S::method),
                          field("rays", &S::rays),
                          field("seconds", &S::seconds),
                          field("cpu", &S::cpuSeconds),
                          field("precompute", &S::precomputeSeconds),
                          field("rmse", &S::rmse),
                          field("maxError", &S::maxError)};
    }
};

// (The ray counts and the seed are not written: the sampled points give the former, the bench
// keeps the latter's default.)
template <>
struct Schema<AccuracyStudyOptions> {
    using S = AccuracyStudyOptions;
    static auto fields() {
        return std::tuple{field("width", &S::width), field("height", &S::height),
                          field("spp", &S::spp), field("referenceRays", &S::referenceRays)};
    }
};

template <>
struct Schema<AccuracyStudy> {
    using S = AccuracyStudy;
    static auto fields() {
        return std::tuple{inlined(&S::options),
                          field("referenceNoise", &S::referenceNoise),
                          field("referenceSeconds", &S::referenceSeconds),
                          field("meanRadiance", &S::meanRadiance),
                          field("exact", &S::exact),
                          NumberOrNull<S>{"equalErrorSeconds", &S::equalErrorSeconds},
                          NumberOrNull<S>{"equalErrorRays", &S::equalErrorRays},
                          field("equalErrorExtrapolated", &S::equalErrorExtrapolated),
                          field("sampled", &S::sampled)};
    }
};

template <>
struct Schema<AccuracyBenchRun> {
    using S = AccuracyBenchRun;
    static auto fields() {
        return std::tuple{field("scene", &S::scene), inlined(&S::study),
                          field("partial", &S::partialTrees)};
    }
};

template <>
struct Schema<PredicateModeResult> {
    using S = PredicateModeResult;
    static auto fields() {
        return std::tuple{field("mode", &S::mode), field("usPerQuery", &S::usPerQuery),
                          field("cpuUsPerQuery", &S::cpuUsPerQuery), field("wrong", &S::wrong),
                          field("otherCount", &S::otherCount)};
    }
};

// Indexed as PredicateStudy::modes: filtered, alwaysExact, naive.
template <>
struct Schema<PredicateCaseResult> {
    using S = PredicateCaseResult;
    static auto fields() {
        return std::tuple{field("case", &S::name),
                          field("queries", &S::queries),
                          element("filteredWrong", &S::wrong, 0),
                          element("alwaysExactWrong", &S::wrong, 1),
                          element("naiveWrong", &S::wrong, 2),
                          element("naiveOtherCount", &S::otherCount, 2),
                          element("filteredOtherCount", &S::otherCount, 0)};
    }
};

template <>
struct Schema<PredicateStudy> {
    using S = PredicateStudy;
    static auto fields() {
        return std::tuple{field("queries", &S::queries), field("modes", &S::modes),
                          field("naiveOtherThanFiltered", &S::naiveOtherThanFiltered),
                          field("perCase", &S::cases),
                          Count<S, PredicateCaseResult>{"cases", &S::cases}};
    }
};

template <>
struct Schema<BuildOptionsRow> {
    using S = BuildOptionsRow;
    static auto fields() {
        return std::tuple{field("scene", &S::scene), field("mergeLeaves", &S::mergeLeaves),
                          field("quadricPruning", &S::quadricPruning), inlined(&S::precompute),
                          field("queryUs", &S::queryUs)};
    }
};

template <>
struct Schema<ScalingRow> {
    using S = ScalingRow;
    static auto fields() {
        return std::tuple{field("scene", &S::scene), field("faces", &S::faces),
                          field("loadSeconds", &S::loadSeconds), inlined(&S::precompute)};
    }
};

template <>
struct Schema<ClickLatency> {
    using S = ClickLatency;
    static auto fields() {
        return std::tuple{field("points", &S::points),
                          field("fragmentsMedianMs", &S::fragmentsMedianMs),
                          field("fragmentsP99Ms", &S::fragmentsP99Ms),
                          field("fragmentsMaxMs", &S::fragmentsMaxMs),
                          field("overBudget", &S::overBudget),
                          field("treePoints", &S::treePoints),
                          field("withTreesMedianMs", &S::withTreesMedianMs),
                          field("withTreesMaxMs", &S::withTreesMaxMs)};
    }
};

template <>
struct Schema<ChainStats> {
    using S = ChainStats;
    static auto fields() {
        return std::tuple{field("manyOccluderPoints", &S::manyOccluderPoints),
                          field("occluderEdges", &S::occluderEdges),
                          field("boundaryEdges", &S::boundaryEdges),
                          field("points", &S::points),
                          field("cells", &S::cells),
                          field("crossingLabels", &S::crossingLabels),
                          field("fragments", &S::fragments),
                          field("oneByOneUs", &S::oneByOneUs),
                          field("partialTrees", &S::partialTrees),
                          field("silhouetteTrees", &S::silhouetteTrees),
                          field("silhouetteUses", &S::silhouetteUses),
                          field("silhouetteKept", &S::silhouetteKept),
                          field("silhouettePoints", &S::silhouettePoints)};
    }
};

template <>
struct Schema<OutlineStats> {
    using S = OutlineStats;
    static auto fields() {
        return std::tuple{field("fragmentEdges", &S::fragmentEdges), field("loops", &S::loops),
                          field("edges", &S::edges), field("integrationUs", &S::integrationUs),
                          field("outlineUs", &S::outlineUs)};
    }
};

template <>
struct Schema<PerPointRow> {
    using S = PerPointRow;
    static auto fields() {
        return std::tuple{
            field("scene", &S::scene),           field("points", &S::points),
            field("exactUs", &S::exactUs),       field("exactMedianUs", &S::exactMedianUs),
            field("exactP99Us", &S::exactP99Us), field("exactMaxUs", &S::exactMaxUs),
            field("click", &S::click),           field("rays16Us", &S::rays16Us),
            field("rays128Us", &S::rays128Us),   field("nodesPerQuery", &S::nodesPerQuery),
            field("chain", &S::chain),           field("fragmentsPerQuery", &S::fragmentsPerQuery),
            field("outline", &S::outline)};
    }
};

template <>
struct Schema<BenchResults> {
    using S = BenchResults;
    static auto fields() {
        return std::tuple{
            field("machine", &S::machine),           field("command", &S::command),
            field("options", &S::options),           field("table1", &S::table1),
            field("accuracy", &S::accuracy),         field("predicates", &S::predicates),
            field("buildOptions", &S::buildOptions), field("scaling", &S::scaling),
            field("perPoint", &S::perPoint),         field("skipped", &S::skipped)};
    }
};

// ---- Writing --------------------------------------------------------------------------------

template <class T>
json toJson(const T& v);

template <class S>
void writeFields(json& object, const S& s) {
    std::apply([&](const auto&... f) { (write(object, s, f), ...); }, Schema<S>::fields());
}

template <class S, class T>
void write(json& o, const S& s, const Field<S, T>& f) {
    o[f.key] = toJson(s.*f.member);
}
template <class S, class T>
void write(json& o, const S& s, const OptionalField<S, T>& f) {
    if (s.*f.member) o[f.key] = toJson(*(s.*f.member));
}
template <class S>
void write(json& o, const S& s, const NumberOrNull<S>& f) {
    const double v = s.*f.member;
    o[f.key] = std::isfinite(v) ? json(v) : json(nullptr);
}
template <class S, class T>
void write(json& o, const S& s, const Inline<S, T>& f) {
    writeFields(o, s.*f.member);
}
template <class S, class T>
void write(json& o, const S& s, const InlineIf<S, T>& f) {
    if (s.*f.member) writeFields(o, *(s.*f.member));
}
template <class S, class E, size_t N>
void write(json& o, const S& s, const Named<S, E, N>& f) {
    json counts = json::object();
    for (size_t i = 0; i < N; ++i) counts[toString(static_cast<E>(i))] = (s.*f.member)[i];
    o[f.key] = std::move(counts);
}
template <class S>
void write(json& o, const S& s, const AnswerCounts<S>& f) {
    o[f.key] = answerTotalsJson(s.*f.member);
}
template <class S, class T, size_t N>
void write(json& o, const S& s, const Element<S, T, N>& f) {
    o[f.key] = toJson((s.*f.member)[f.index]);
}
template <class S, class T>
void write(json& o, const S& s, const Count<S, T>& f) {
    o[f.key] = (s.*f.member).size();
}

template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};

template <class T>
json toJson(const T& v) {
    if constexpr (HasSchema<T>) {
        json object = json::object();
        writeFields(object, v);
        return object;
    } else if constexpr (IsVector<T>::value || std::is_array_v<T>) {
        json array = json::array();
        for (const auto& e : v) array.push_back(toJson(e));
        return array;
    } else {
        static_assert(std::is_arithmetic_v<T> || std::is_same_v<T, std::string>);
        return json(v);
    }
}

// ---- Reading --------------------------------------------------------------------------------

[[noreturn]] void fail(const std::string& where, const std::string& why) {
    throw BenchJsonError("bench.json: " + where + ": " + why);
}

std::string child(const std::string& where, const std::string& key) {
    return where.empty() ? key : where + "." + key;
}

// One object of bench.json, read key by key; finish() refuses the keys nobody took.
class ObjectReader {
  public:
    ObjectReader(const json& j, std::string where) : j_(j), where_(std::move(where)) {
        if (!j_.is_object()) fail(name(), "expected an object");
    }
    bool has(const char* key) const { return j_.contains(key); }
    const json& take(const char* key) {
        const auto it = j_.find(key);
        if (it == j_.end()) fail(name(), std::string("missing \"") + key + "\"");
        taken_.insert(key);
        return *it;
    }
    std::string at(const char* key) const { return child(where_, key); }
    void finish() const {
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (taken_.count(it.key()) == 0) fail(name(), "unknown key \"" + it.key() + "\"");
    }

  private:
    std::string name() const { return where_.empty() ? "(root)" : where_; }

    const json& j_;
    std::string where_;
    std::set<std::string> taken_;
};

template <class T>
void fromJson(const json& j, const std::string& where, T& v);

template <class S>
void readFields(ObjectReader& r, S& s) {
    std::apply([&](const auto&... f) { (read(r, s, f), ...); }, Schema<S>::fields());
}

template <class S, class T>
void read(ObjectReader& r, S& s, const Field<S, T>& f) {
    fromJson(r.take(f.key), r.at(f.key), s.*f.member);
}
template <class S, class T>
void read(ObjectReader& r, S& s, const OptionalField<S, T>& f) {
    (s.*f.member).reset();
    if (!r.has(f.key)) return;
    T v{};
    fromJson(r.take(f.key), r.at(f.key), v);
    s.*f.member = std::move(v);
}
template <class S>
void read(ObjectReader& r, S& s, const NumberOrNull<S>& f) {
    const json& j = r.take(f.key);
    if (j.is_null())
        s.*f.member = std::numeric_limits<double>::quiet_NaN();
    else
        fromJson(j, r.at(f.key), s.*f.member);
}
template <class S, class T>
void read(ObjectReader& r, S& s, const Inline<S, T>& f) {
    readFields(r, s.*f.member);
}
template <class S, class T>
void read(ObjectReader& r, S& s, const InlineIf<S, T>& f) {
    (s.*f.member).reset();
    if (!r.has(f.marker)) return;
    T v{};
    readFields(r, v);
    s.*f.member = std::move(v);
}
template <class S, class E, size_t N>
void read(ObjectReader& r, S& s, const Named<S, E, N>& f) {
    ObjectReader counts(r.take(f.key), r.at(f.key));
    for (size_t i = 0; i < N; ++i) {
        const char* name = toString(static_cast<E>(i));
        fromJson(counts.take(name), child(r.at(f.key), name), (s.*f.member)[i]);
    }
    counts.finish();
}
// A bench.json written before the horizon-clipped answer has no count for it: 0 (its "fully
// visible" count holds both; the report of such a file says so); one written before the
// light-edge path none for that (0: its points were sampled then). Every other count is
// required.
template <class S>
void read(ObjectReader& r, S& s, const AnswerCounts<S>& f) {
    ObjectReader counts(r.take(f.key), r.at(f.key));
    for (size_t i = 0; i < kAnswers; ++i) {
        const Answer a = static_cast<Answer>(i);
        const char* name = toString(a);
        if ((a == Answer::HorizonClipped || a == Answer::LightEdges) && !counts.has(name)) {
            (s.*f.member)[i] = 0;
            continue;
        }
        fromJson(counts.take(name), child(r.at(f.key), name), (s.*f.member)[i]);
    }
    counts.finish();
}
template <class S, class T, size_t N>
void read(ObjectReader& r, S& s, const Element<S, T, N>& f) {
    fromJson(r.take(f.key), r.at(f.key), (s.*f.member)[f.index]);
}
template <class S, class T>
void read(ObjectReader& r, S& s, const Count<S, T>& f) {
    size_t n = 0;
    fromJson(r.take(f.key), r.at(f.key), n);
    if (n != (s.*f.member).size())
        fail(r.at(f.key),
             std::to_string(n) + ", but " + std::to_string((s.*f.member).size()) + " entries");
}

template <class T>
void fromJson(const json& j, const std::string& where, T& v) {
    if constexpr (HasSchema<T>) {
        ObjectReader r(j, where);
        readFields(r, v);
        r.finish();
    } else if constexpr (IsVector<T>::value) {
        if (!j.is_array()) fail(where, "expected an array");
        v.assign(j.size(), {});
        for (size_t i = 0; i < j.size(); ++i)
            fromJson(j[i], where + "[" + std::to_string(i) + "]", v[i]);
    } else if constexpr (std::is_array_v<T>) {
        if (!j.is_array() || j.size() != std::extent_v<T>)
            fail(where, "expected an array of " + std::to_string(std::extent_v<T>));
        for (size_t i = 0; i < std::extent_v<T>; ++i)
            fromJson(j[i], where + "[" + std::to_string(i) + "]", v[i]);
    } else if constexpr (std::is_same_v<T, bool>) {
        if (!j.is_boolean()) fail(where, "expected true or false");
        v = j.get<bool>();
    } else if constexpr (std::is_integral_v<T>) {
        const bool ok = j.is_number_unsigned() ||
                        (j.is_number_integer() && (std::is_signed_v<T> || j.get<int64_t>() >= 0));
        if (!ok) fail(where, std::is_signed_v<T> ? "expected an integer" : "expected a count");
        v = j.get<T>();
    } else if constexpr (std::is_floating_point_v<T>) {
        if (!j.is_number()) fail(where, "expected a number");
        v = j.get<T>();
    } else {
        static_assert(std::is_same_v<T, std::string>);
        if (!j.is_string()) fail(where, "expected a string");
        v = j.get<std::string>();
    }
}

}  // namespace

nlohmann::json benchJson(const BenchResults& results) { return toJson(results); }

BenchResults readBenchJson(const nlohmann::json& bench) {
    BenchResults results;
    fromJson(bench, "", results);
    return results;
}

}  // namespace penumbra::cli
