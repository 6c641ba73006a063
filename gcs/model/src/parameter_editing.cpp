#include "uav/gcs/parameter_editing.hpp"

#include <cstdio>
#include <stdexcept>

#include "uav/gcs/gcs_model.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::gcs {
namespace {

std::string CheckValue(const ParameterEntry& e, double v, bool armed) {
  if (v < e.min || v > e.max)
    return e.name + " = " + FormatParameterValue(v) + " is outside [" + FormatParameterValue(e.min) + ", " +
           FormatParameterValue(e.max) + "] " + e.unit;
  if (v == e.value) return "";
  if (e.apply == ParamApply::kAtStart) return e.name + " is read only at start (the vehicle file or --param)";
  if (e.apply == ParamApply::kOnGround && armed) return e.name + " changes only while disarmed";
  return "";
}

}  // namespace

std::string CheckParameterValue(const ParameterTable& table, const std::string& name, const std::string& text, bool armed,
                                double* value) {
  const ParameterEntry* e = table.Find(name);
  if (!e) return "the vehicle has no parameter '" + name + "'";
  const std::optional<double> v = ParseDecimal(text);
  if (!v) return name + ": '" + text + "' is not a finite decimal number";
  *value = *v;
  return CheckValue(*e, *v, armed);
}

ParameterLoad PlanParameterLoad(const ParameterTable& table, const std::vector<std::pair<std::string, double>>& file,
                                bool armed) {
  ParameterLoad load;
  for (const auto& [name, v] : file) {
    const ParameterEntry* e = table.Find(name);
    if (!e) {
      load.problems.push_back("the vehicle has no parameter '" + name + "'");
      continue;
    }
    if (v == e->value) {
      ++load.unchanged;
      continue;
    }
    const std::string why = CheckValue(*e, v, armed);
    if (why.empty()) load.to_send.emplace_back(name, v);
    else load.problems.push_back(why);
  }
  return load;
}

}  // namespace uav::gcs

// ---- The operator's actions (GcsModel), here beside their checks.
namespace uav::gcs {
namespace {

const ParameterTable* TableOf(const VehicleModel* v) {
  if (!v) return nullptr;
  const auto& received = v->reports.Get<ParameterTable>();
  return received.newest ? &*received.newest : nullptr;
}

}  // namespace

bool GcsModel::SetParameter(const std::string& name, const std::string& text, double now) {
  const VehicleModel* v = selected();
  const ParameterTable* table = TableOf(v);
  if (!table) {
    log_.Add(now, selected_, "parameter not sent: no parameter table from the vehicle yet", Severity::kWarning);
    return false;
  }
  double value = 0.0;
  const std::string why = CheckParameterValue(*table, name, text, v->armed, &value);
  if (!why.empty()) {
    log_.Add(now, selected_, "parameter not sent: " + why, Severity::kWarning);
    return false;
  }
  if (v->mavlink) return commands_.SubmitForeignParameter(name, FormatParameterValue(value), selected_, now, log_);
  return commands_.Submit("param " + name + " " + FormatParameterValue(value), selected_, now, log_);
}

bool GcsModel::SaveParameters(const std::string& path, ParameterFileFormat format, double now) {
  const ParameterTable* table = TableOf(selected());
  try {
    if (!table) throw std::runtime_error("no parameter table from the vehicle yet");
    WriteFileAtomically(path, FormatParameterFile(*table, format, selected_));
  } catch (const std::exception& e) {
    log_.Add(now, selected_, std::string("parameters not saved: ") + e.what(), Severity::kWarning);
    return false;
  }
  log_.Add(now, selected_,
           "parameters saved to " + path + " (" + std::to_string(table->entries.size()) + ", " +
               (format == ParameterFileFormat::kQgc ? "QGroundControl format)" : "vehicle-file format)"),
           Severity::kInfo);
  return true;
}

bool GcsModel::LoadParameters(const std::string& path, double now) {
  const VehicleModel* v = selected();
  const ParameterTable* table = TableOf(v);
  ParameterLoad load;
  try {
    if (!table) throw std::runtime_error("no parameter table from the vehicle yet");
    load = PlanParameterLoad(*table, ParseParameterFile(ReadTextFile(path, "parameter file"), path), v->armed);
  } catch (const std::exception& e) {
    log_.Add(now, selected_, std::string("parameters not loaded: ") + e.what(), Severity::kWarning);
    return false;
  }
  for (const std::string& p : load.problems) log_.Add(now, selected_, "parameter file: " + p, Severity::kWarning);
  int sent = 0;
  for (const auto& [name, value] : load.to_send)
    sent += v->mavlink ? commands_.SubmitForeignParameter(name, FormatParameterValue(value), selected_, now, log_)
                       : commands_.Submit("param " + name + " " + FormatParameterValue(value), selected_, now, log_);
  log_.Add(now, selected_,
           path + ": " + std::to_string(sent) + " changes sent, " + std::to_string(load.unchanged) + " unchanged, " +
               std::to_string(load.problems.size()) + " not sent",
           load.problems.empty() ? Severity::kInfo : Severity::kWarning);
  return true;
}

}  // namespace uav::gcs
