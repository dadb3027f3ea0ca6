// The fill report as JSON, the form scripts rely on (keys listed in the README).
#pragma once

#include <nlohmann/json.hpp>

#include "foldfill/inpaint.h"

namespace foldfill {

nlohmann::json to_json(const HoleReport& hole);
nlohmann::json to_json(const FillReport& report);

}  // namespace foldfill
