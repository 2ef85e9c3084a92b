// Looking up an entry of a table by its name, as the command line names it.
#pragma once

#include <string>

#include "hrbench/util/error.h"

namespace hrbench {

// The entry of _table_ (a sequence of records with a `name`) named _name_; throws
// InputError "unknown WHAT 'NAME' (choose one of: a, b, ...)" otherwise.
template <typename Table>
const auto &FindNamed(const Table &table, const std::string &name, const std::string &what) {
    std::string names;
    for (const auto &entry : table) {
        if (entry.name == name)
            return entry;
        names += (names.empty() ? "" : ", ") + std::string(entry.name);
    }
    throw InputError("unknown " + what + " '" + name + "' (choose one of: " + names + ")");
}

// The name of the entry of _table_ whose member _field_ equals _value_: the reverse of
// FindNamed, for enums listed in a table; "unknown" where none does.
template <typename Table, typename Field, typename Value>
std::string NameOf(const Table &table, Field field, const Value &value) {
    for (const auto &entry : table)
        if (entry.*field == value)
            return entry.name;
    return "unknown";
}

}  // namespace hrbench
