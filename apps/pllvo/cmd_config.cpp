// `pllvo config --dump`: every configuration key with its default, read off the code that
// loads it (ConfigNode::recording), so the reference cannot drift from the code.
#include <cstdio>

#include "commands.h"
#include "pllvo/nn/nn_config.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo::cli {

void add_config_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("config", "configuration keys with their defaults, as the code reads them");
  auto section = std::make_shared<std::string>("vo");
  auto dump = std::make_shared<bool>(false);
  cmd->add_flag("--dump", *dump, "print every key with its default, one 'section.key: value' a line")->required();
  cmd->add_option("--section", *section,
                  "vo: the VO config (config/vo.yaml with its geometry, backend and lines sections); "
                  "nn: the networks (config/nn.yaml)")
      ->check(CLI::IsMember({"vo", "nn"}))
      ->capture_default_str();
  cmd->callback([section, dump] {
    const ConfigNode recorder = ConfigNode::recording();
    if (*section == "vo") vo::VoConfig().read(recorder);
    else nn::NnConfig::from_yaml(recorder);
    for (const auto& d : recorder.recorded()) std::printf("%s: %s\n", d.key.c_str(), d.value.c_str());
  });
}

}  // namespace pllvo::cli
