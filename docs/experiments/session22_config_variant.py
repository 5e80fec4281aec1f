# Session 22 (docs/vo.md): config/vo.yaml with dotted overrides, written to cfg/NAME.yaml.
# Usage: python3 docs/experiments/session22_config_variant.py NAME backend.pose_refiner.point_loss=cauchy ...
# then: pllvo run SEQ --config cfg/NAME.yaml --out DIR [--single-thread] [--first K] [--mono]
import os
import sys

import yaml

name, sets = sys.argv[1], sys.argv[2:]
here = os.path.dirname(os.path.abspath(__file__))
config = yaml.safe_load(open(os.path.join(here, '..', '..', 'config', 'vo.yaml')))
for s in sets:
    key, value = s.split('=', 1)
    node = config
    *path, last = key.split('.')
    for k in path:
        if node.get(k) is None:
            node[k] = {}
        node = node[k]
    node[last] = yaml.safe_load(value)
os.makedirs('cfg', exist_ok=True)
yaml.safe_dump(config, open(os.path.join('cfg', name + '.yaml'), 'w'))
