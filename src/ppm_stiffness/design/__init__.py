"""Design files and their schema: what a manipulator is made of (SI units)."""

from ppm_stiffness.design.io import (
    default_design,
    design_from_dict,
    design_to_dict,
    dump_design,
    load_design,
    save_design,
)
from ppm_stiffness.design.schema import SCHEMA_VERSION, Design, WorkspaceModel
from ppm_stiffness.legs.parts import (
    ActuatorModel,
    BearingModel,
    GuideModel,
    RevoluteModel,
    SectionModel,
)

__all__ = [
    "SCHEMA_VERSION",
    "ActuatorModel",
    "BearingModel",
    "Design",
    "GuideModel",
    "RevoluteModel",
    "SectionModel",
    "WorkspaceModel",
    "default_design",
    "design_from_dict",
    "design_to_dict",
    "dump_design",
    "load_design",
    "save_design",
]
