import sys
from PIL import Image
import numpy as np
a=np.asarray(Image.open(sys.argv[1])); b=np.asarray(Image.open(sys.argv[2]))
print(sys.argv[1], sys.argv[2], "identical" if a.shape==b.shape and (a==b).all() else "DIFFER %d px"%((a!=b).any(axis=-1).sum() if a.shape==b.shape else -1))
