// The run record (record.h): the counter table that names every counter, the JSON and
// table writers, the context of a run, and the record of each counting method.
#include <catch2/catch.hpp>

#include <algorithm>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "generators.h"
#include "hrbench/hrbench.h"
#include "refinement_helpers.h"

using namespace hrbench;
using nlohmann::json;

namespace {

// A record whose counters all differ from each other and from 0.
RunRecord DistinctRecord() {
    RunRecord record;
    record.method = "enumerate";
    record.seconds = 0.125;
    uint64_t value = 1000;
    for (const CounterInfo &c : CounterTable()) {
        if (c.scalar)
            record.counters.*c.scalar = value++;
        else
            record.counters.*c.histogram = {value++, value++, 7};
    }
    return record;
}

RefineOptions CountOnly(double eps) {
    RefineOptions o;
    o.eps = eps;
    o.storeLinks = false;
    return o;
}

}  // namespace

TEST_CASE("The counter table names every counter once, with its category and unit", "[record]") {
    std::set<std::string> names;
    size_t scalars = 0, histograms = 0;
    for (const CounterInfo &c : CounterTable()) {
        INFO(c.name);
        CHECK(names.insert(c.name).second);  // unique
        CHECK((c.scalar == nullptr) != (c.histogram == nullptr));
        CHECK(std::set<std::string>{"tree", "refine", "visibility"}.count(c.category) == 1);
        CHECK(std::string(c.unit).size() > 0);
        CHECK(std::string(c.doc).size() > 0);
        scalars += c.scalar != nullptr;
        histograms += c.histogram != nullptr;
    }
    // Every member of Counters is in the table: a counter added to the struct but not to
    // the table would change its size.
    CHECK(sizeof(Counters) ==
          scalars * sizeof(uint64_t) + histograms * sizeof(std::vector<uint64_t>));
    // The scalars come first, then the histograms (output order).
    const auto &table = CounterTable();
    auto firstHistogram = std::find_if(table.begin(), table.end(),
                                       [](const CounterInfo &c) { return c.histogram != nullptr; });
    CHECK(std::all_of(firstHistogram, table.end(),
                      [](const CounterInfo &c) { return c.histogram != nullptr; }));
    for (const char *name :
         {"nodes", "leaves", "links", "oracle_calls", "max_depth", "forced_links", "culled_pairs",
          "root_pairs", "rays", "visibility_queries", "occluded_pairs", "nodes_per_depth",
          "links_per_depth"})
        CHECK(names.count(name) == 1);
}

TEST_CASE("Every counter appears in the JSON record with its value", "[record]") {
    Scene scene = MakeScene("parallel", {{"l", 64}, {"d", 1}});
    RunRecord record = DistinctRecord();
    json j = RunToJson(scene, CountOnly(0.25), record);
    for (const CounterInfo &c : CounterTable()) {
        INFO(c.name);
        REQUIRE(j.contains(c.name));
        if (c.scalar)
            CHECK(j[c.name].get<uint64_t>() == record.counters.*c.scalar);
        else
            CHECK(j[c.name].get<std::vector<uint64_t>>() == record.counters.*c.histogram);
    }
    CHECK(j["method"] == "enumerate");
    CHECK(j["seconds"] == 0.125);
    CHECK(j["schema_version"] == kRunSchemaVersion);
    CHECK(j["version"] == EngineVersion());
    CHECK(j["scene"] == "parallel");
    CHECK(j["patches"] == 2);
    CHECK(j["dimension"] == 2);
    CHECK(j["eps"] == 0.25);
    CHECK(j["oracle"] == "garmann");
    CHECK(j["mode"] == "count-only");
    CHECK(j["subdivision"] == "binary");
    CHECK(j["visibility"] == "none");
    CHECK(j["rays_per_side"].is_null());
    CHECK(RunToJson(MakeScene("parallel3d", {}), CountOnly(0.25), record)["dimension"] == 3);
}

TEST_CASE("The human table prints every counter", "[record]") {
    RunRecord record = DistinctRecord();
    json j = RunToJson(MakeScene("parallel", {}), CountOnly(0.25), record);
    std::ostringstream table;
    PrintRunTable(j, table);
    for (const CounterInfo &c : CounterTable()) {
        INFO(c.name);
        CHECK_THAT(table.str(), Catch::Contains(c.name));
        if (c.scalar)
            CHECK_THAT(table.str(), Catch::Contains(std::to_string(record.counters.*c.scalar)));
    }
    CHECK_THAT(table.str(), Catch::Contains("seconds"));
}

TEST_CASE("The context of a record names the build, the commit and the machine", "[record]") {
    json context = RunContext();
    for (const char *key : {"version", "build_type", "compiler", "build_flags", "git_commit",
                            "cpu_model", "date", "host"}) {
        INFO(key);
        REQUIRE(context.contains(key));
        CHECK(context[key].is_string());
        CHECK(!context[key].get<std::string>().empty());
    }
    CHECK(context["version"] == EngineVersion());
    CHECK_THAT(context["build_flags"].get<std::string>(), Catch::Contains("-ffp-contract=off"));
    Scene scene = MakeScene("parallel", {});
    json j = RunToJson(scene, CountOnly(0.5), RunRecord{});
    for (const char *key : {"git_commit", "compiler", "build_flags", "cpu_model"})
        CHECK(j["context"][key] == context[key]);
}

TEST_CASE("The translation method's record has the enumerate record's counters",
          "[record][translation]") {
    Scene scene = MakeScene("parallel", {{"l", 64}, {"d", 1}});
    RunRecord enumerated = Count(scene, CountOnly(0.25), "enumerate");
    RunRecord translated = Count(scene, CountOnly(0.25), "translation");
    CHECK(enumerated.method == "enumerate");
    CHECK(translated.method == "translation");
    CHECK(enumerated.counters.links == 5092);
    CHECK(enumerated.counters.oracleCalls == 10183);
    CHECK(hrbench_test::CounterDifferences(enumerated.counters, translated.counters) == "");
    CHECK(enumerated.seconds >= 0);
    CHECK(translated.seconds >= 0);
    json a = RunToJson(scene, CountOnly(0.25), enumerated);
    json b = RunToJson(scene, CountOnly(0.25), translated);
    for (const CounterInfo &c : CounterTable()) {
        INFO(c.name);
        CHECK(a[c.name] == b[c.name]);
    }
}

TEST_CASE("Count knows the methods Methods() lists, and no other", "[record]") {
    std::vector<std::string> names;
    for (const MethodInfo &m : Methods())
        names.push_back(m.name);
    CHECK(names == std::vector<std::string>{"enumerate", "translation"});
    Scene scene = MakeScene("parallel", {{"l", 8}, {"d", 1}});
    for (const std::string &name : names)
        CHECK(Count(scene, CountOnly(0.5), name).method == name);
    CHECK_THROWS_AS(Count(scene, CountOnly(0.5), "fast"), InputError);
    CHECK_THROWS_WITH(Count(scene, CountOnly(0.5), "fast"), Catch::Contains("fast"));
}
