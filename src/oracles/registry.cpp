#include "hrbench/oracles/registry.h"

#include "hrbench/util/error.h"
#include "util/named.h"

namespace hrbench {

std::vector<OracleInfo> OracleInfos() {
    std::vector<OracleInfo> infos;
    AllOracles::ForEach([&](auto tag) { infos.push_back(tag.Info()); });
    return infos;
}

const OracleInfo &FindOracle(const std::string &name) {
    static const std::vector<OracleInfo> infos = OracleInfos();
    return FindNamed(infos, name, "oracle");
}

std::vector<std::string> OraclesReading(const std::string &option) {
    std::vector<std::string> names;
    for (const OracleInfo &info : OracleInfos())
        if (info.Reads(option))
            names.push_back(info.name);
    return names;
}

}  // namespace hrbench
