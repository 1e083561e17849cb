#pragma once
/**
 * @file scene.h
 * A scene: everything a run needs, read from a deal.II ParameterHandler file
 * in SI units, validated before any work is done (doc/user-guide.md, "Running scenes"
 * and "Scene files"). Internally the code works in scaled units (struct Units).
 */
#include <granhydro/base/errors.h>
#include <granhydro/base/units.h>
#include <granhydro/boundary/boundary_conditions.h>
#include <granhydro/boundary/moving_frame.h>
#include <granhydro/convection/settings.h>
#include <granhydro/io/settings.h>
#include <granhydro/mesh/settings.h>
#include <granhydro/scene/adaptivity.h>
#include <granhydro/scene/dense_closure.h>
#include <granhydro/scene/diffusion_step.h>
#include <granhydro/scene/domain.h>
#include <granhydro/scene/effects.h>
#include <granhydro/scene/initial_state.h>
#include <granhydro/scene/material.h>
#include <granhydro/scene/numerics.h>
#include <granhydro/scene/output.h>
#include <granhydro/scene/time.h>

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace granhydro::scene
{
  /**
   * A scene is the aggregate of its subsections (as deal.II's step-33 AllParameters): each
   * base declares, parses and checks its own entries, so `scene.field` reads every entry
   * directly. What only the whole scene knows (the unit system, the settings the layers
   * below need, whether the diffusion step runs) lives here.
   */
  struct Scene : DomainParameters,
                 MaterialParameters,
                 DenseClosureParameters,
                 InitialStateParameters,
                 NumericsParameters,
                 EffectsParameters,
                 DiffusionStepParameters,
                 AdaptivityParameters,
                 TimeParameters,
                 OutputParameters
  {
    std::string  source    = "<default scene>";
    unsigned int dimension = 2;
    /// how the scene was read, for the run records: the -p overrides as given, and the
    /// scene they gave as a scene file of its own (expanded_scene_text())
    std::vector<std::string> overrides;
    std::string              expanded_text;

    /// true if the implicit diffusion/source step V runs (granular model only)
    bool diffusion_active() const;

    Units units() const;
    /// what the convective step needs (convection/settings.h)
    convection::ConvectionSettings convection_settings() const;
    /// what the mesh needs (mesh/settings.h)
    mesh::MeshSettings mesh_settings() const;
    /// what the output needs (io/settings.h)
    io::OutputSettings output_settings() const;
    /// the vibrated container's motion in SI units (boundary/moving_frame.h; at rest
    /// without a vibration)
    boundary::MovingFrame moving_frame() const;
  };

  /// declare every parameter with its default, pattern and documentation
  void declare_scene_parameters(dealii::ParameterHandler &prm);

  /// the embedded default scene (a 2D cylindrical blast in the ideal-gas limit)
  std::string default_scene_text();

  /**
   * Read a scene from a file ("" = embedded default), validate it and
   * return it. Throws SceneError naming the offending parameter.
   */
  /// overrides: "Section/Name=value" (nested sections joined by '/'), applied after the
  /// file as if its last lines set them (command line -p)
  Scene read_scene(const std::string &filename, const std::vector<std::string> &overrides = {});

  /// the same from a string in .prm syntax (tests)
  Scene parse_scene(const std::string &text, const std::string &source_name,
                    const std::vector<std::string> &overrides = {});

  /**
   * The scene of `filename` ("" = embedded default) with its includes and overrides
   * applied, as a scene file of its own: every parameter in declaration order, in deal.II's
   * PRM format with the documentation as comments (granhydro --print-parameters,
   * <base>_parameters.prm). 'Domain/Mesh file', relative to the scene file, is made
   * absolute; the paths relative to the working directory (Output/Directory, Initial
   * state/Checkpoint) stay as given. Read, not validated: throws SceneError for what
   * cannot be read (unknown parameter, value against its pattern, bad override).
   */
  std::string expanded_scene_text(const std::string              &filename,
                                  const std::vector<std::string> &overrides = {});

  /// the effects the scene activates, each with the reason (doc/user-guide.md, "Running scenes")
  std::vector<std::pair<std::string, std::string>> active_effects(const Scene &scene);

  /// pi and the scene's 'Initial state/Constants' for the expressions; throws SceneError
  std::map<std::string, double> expression_constants(const Scene &scene);

  /// check every impossible combination; throws SceneError
  void validate(const Scene &scene);
} // namespace granhydro::scene
