#!/usr/bin/env python3
"""Writes the hand-made seed inputs of fuzz/corpus/{mesh,field,model}/ (run from anywhere).

File names say what each seed is; the first byte of a mesh seed picks its extension for fuzz_mesh
(0 = .ply, 1 = .obj, 2 = .off, 3 = .stl) and of a field seed its format for fuzz_field (0 = .blk, 1 = .csv).
Regression inputs for fixed findings (regress_*) are kept as the fuzzer found them, not written here.
"""
import json, os, struct

os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus"))
def w(path, data):
    mode = 'wb' if isinstance(data, bytes) else 'w'
    with open(path, mode) as f: f.write(data)
V=[(0,0,0),(1,0,0),(1,1,0.5),(0,1,0.25)]
hdr=lambda fmt,vprops,nv,nf,fprops="property list uchar int vertex_indices\n": ("ply\nformat %s 1.0\ncomment gridshell fuzz seed\nelement vertex %d\n%selement face %d\n%send_header\n"%(fmt,nv,vprops,nf,fprops))
xyz="property float x\nproperty float y\nproperty float z\n"
rgb="property uchar red\nproperty uchar green\nproperty uchar blue\n"
# mesh: ascii ply with colours, red supports at 0 and 2
s=hdr("ascii",xyz+rgb,4,2)
cols=[(255,0,0),(192,192,192),(255,0,0),(192,192,192)]
s+="".join("%g %g %g %d %d %d\n"%(v+c) for v,c in zip(V,cols))+"3 0 1 2\n3 0 2 3\n"
w("mesh/0_ascii_ply_red_supports","0"+s)
# ascii ply quad without colours
s=hdr("ascii",xyz,4,1)+"".join("%g %g %g\n"%v for v in V)+"4 0 1 2 3\n"
w("mesh/0_ascii_ply_quad","0"+s)
# binary little endian, double coordinates, colours, extra support flag (as write_ply does)
vp="property double x\nproperty double y\nproperty double z\n"+rgb+"property uchar support\n"
b=hdr("binary_little_endian",vp,4,2).encode()
for v,c in zip(V,cols): b+=struct.pack("<3d3BB",*v,*c,1 if c[0]==255 and c[1]==0 else 0)
for f in [(0,1,2),(0,2,3)]: b+=struct.pack("<B3i",3,*f)
w("mesh/0_binary_le_ply",b"0"+b)
# binary big endian, float + extra double property, extra element, face flags
vp=xyz+"property double quality\n"
h=("ply\nformat binary_big_endian 1.0\nelement vertex 4\n"+vp+"element material 1\nproperty uchar kind\nelement face 2\nproperty list uchar int vertex_indices\nproperty int flags\nend_header\n").encode()
for v in V: h+=struct.pack(">3fd",*v,7.5)
h+=bytes([3])
for f in [(0,1,2),(0,2,3)]: h+=struct.pack(">B3ii",3,*f,42)
w("mesh/0_binary_be_ply_extra_elements",b"0"+h)
# broken PLYs
s=hdr("ascii",xyz,4,2)+"".join("%g %g %g\n"%v for v in V)+"3 0 1 2\n"
w("mesh/0_ascii_ply_truncated","0"+s)
s=hdr("ascii",xyz,4,1)+"".join("%g %g %g\n"%v for v in V)+"3 0 1 9\n"
w("mesh/0_ascii_ply_bad_index","0"+s)
w("mesh/0_binary_ply_truncated",b"0"+hdr("binary_little_endian",xyz,4,2).encode()+b"\0"*20)
# near-red supports (another exporter's idea of red)
s=hdr("ascii",xyz+rgb,4,2)
cols2=[(254,0,0),(200,200,200),(255,10,10),(200,200,200)]
s+="".join("%g %g %g %d %d %d\n"%(v+c) for v,c in zip(V,cols2))+"3 0 1 2\n3 0 2 3\n"
w("mesh/0_ascii_ply_near_red","0"+s)
# OBJ
w("mesh/1_obj_quad_negative_indices","1# a quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -4/1/1 -3/1/1 -2/1/1 -1/1/1\nv 2 0.5 0\nf 2 5 3\n")
w("mesh/1_obj_triangles","1v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0.25\nf 1 2 3\nf 1 3 4\n")
w("mesh/1_obj_messy","1# unreferenced, duplicate and repeated-corner vertices\nv 9 9 9\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 2 3 4\nf 2 5 4 6\nf 2 2 3\n")
w("mesh/1_obj_out_of_range","1v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
w("mesh/1_obj_concave","1# two notched pentagons: one planar, one with its notch lifted out of its plane\nv 0 0 0\nv 2 0 0\nv 2 2 0\nv 1 0.5 0\nv 0 2 0\nv 4 0 0\nv 4 2 0\nv 3 1.5 1\nf 3 4 5 1 2\nf 2 6 7 8 3\n")
# OFF
w("mesh/2_off","2OFF\n# comment\n4 2 0\n0 0 0\n1 0 0\n1 1 0.5\n0 1 0.25\n3 0 1 2\n3 0 2 3\n")
w("mesh/2_off_polygon","2OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0.5 0\n4 0 1 2 3\n3 1 4 2\n")
w("mesh/2_off_truncated","2OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n")
# STL: ascii, binary (with and without "solid" in its header), binary declaring too many facets
T=[(V[0],V[1],V[2]),(V[0],V[2],V[3])]
s="solid seed\n"+"".join("facet normal 0 0 1\nouter loop\n"+"".join("vertex %g %g %g\n"%v for v in t)+"endloop\nendfacet\n" for t in T)+"endsolid seed\n"
w("mesh/3_stl_ascii","3"+s)
def stl(header,n):
    b=header.ljust(80,b" ")+struct.pack("<I",n)
    for t in T: b+=struct.pack("<3f",0,0,1)+b"".join(struct.pack("<3f",*v) for v in t)+b"\0\0"
    return b
w("mesh/3_stl_binary",b"3"+stl(b"binary seed",2))
w("mesh/3_stl_binary_solid_header",b"3"+stl(b"solid binary seed",2))
w("mesh/3_stl_binary_short",b"3"+stl(b"binary seed",7))
# field: 3x3 patch vertices (fuzz_field.cpp)
pts=[(i-1.0,j-1.0,0.3 if (i,j)==(1,1) else 0.0) for j in range(3) for i in range(3)]
s="x\ty\tz\ts1\tv1x\tv1y\tv1z\ts2\tv2x\tv2y\tv2z\n"
for k,p in enumerate(pts):
    s+="\t".join("%g"%x for x in (*p, 1000+10*k, 1,0,0, -500, 0,1,0))+"\n"
w("field/0_blk","0"+s)
s="x y z s1 v1x v1y v1z s2 v2x v2y v2z\n"
for k,p in enumerate(pts[:4]):
    s+=" ".join("%g"%x for x in (p[0],p[1],p[2]+0.2, -2e5, 0.7,0.7,0, 3e4, -0.7,0.7,0))+"\n"
w("field/0_blk_few_points_offset","0"+s)
w("field/0_blk_nan","0x y z s1 v1x v1y v1z s2 v2x v2y v2z\n0 0 0 nan 1 0 0 0 0 1 0\n")
w("field/0_blk_short_row","0header\n0 0 0 1 1 0 0 2 0 1\n")
s="vertex,s1,s2,d1x,d1y,d1z\n"+"".join("%d,%g,%g,1,0,0\n"%(k,1e3*k,-1e3) for k in range(9))
w("field/1_csv","1"+s)
s="".join("%d;%g;%g;0;1;0.1\r\n"%(k,5.0,1.0) for k in range(9))
w("field/1_csv_no_header_semicolons","1"+s)
s="vertex,s1,s2,d1x,d1y,d1z\n"+"".join("%d,%g,%g,1,0,0\n"%(k,1,1) for k in range(8))
w("field/1_csv_missing_vertex","1"+s)
w("field/1_csv_zero_direction","10,1,1,0,0,0\n")
w("field/1_csv_bad_id","1-1,1,1,1,0,0\n1.5,1,1,1,0,0\n")
# models
nodes=[[0,0,0],[1,0,0],[1,1,0.2],[0,1,0.1]]
frame={"nodes":nodes,
 "sections":{"bar":{"shape":"circle","diameter":0.05},"box":{"A":1e-3,"Iy":1e-6,"Iz":2e-6,"J":1e-6,"up":[0,0,1]}},
 "materials":{"steel":{"E":2.1e11,"nu":0.3,"density":7850}},
 "members":[{"nodes":[0,1],"section":"bar","material":"steel"},{"nodes":[1,2],"section":"box","elements":3},
            {"nodes":[2,3],"section":"bar","type":"truss"},{"nodes":[3,0],"section":"bar","type":"beam"}],
 "faces":[[0,1,2,3]],
 "supports":[{"node":0,"fix":["ux","uy","uz","rx","ry","rz"]},{"node":2}],
 "loads":[{"node":1,"force":[0,0,-1000],"moment":[0,10,0]},{"type":"surface","q":[0,0,-500]},
          {"type":"projected","q":[0,0,-100]},{"type":"self_weight","g":9.81}],
 "analysis":{"linear":True,"buckling":True,"nonlinear":False,"nonlinear_static":1.5}}
w("model/frame.json",json.dumps(frame,indent=1))
cases=dict(frame); del cases["loads"]
cases["materials"]={"steel":{"E":2.1e11,"density":7850,"fy":3.55e8}}
cases["load_cases"]={"G":{"type":"permanent","loads":[{"type":"self_weight"},{"type":"surface","q":[0,0,-400]}]},
                     "S":{"type":"variable","loads":[{"type":"projected","q":[0,0,-1000]},{"node":1,"force":[0,0,-1]}]}}
cases["combinations"]={"ULS":{"G":1.35,"S":1.5},"SLS":{"G":1,"S":1}}
cases["analysis"]={"nonlinear":True,"stop_displacement":0.5,"stop_lambda":10,"max_steps":20}
w("model/frame_load_cases.json",json.dumps(cases,indent=1))
shell={"nodes":nodes,"triangles":[[0,1,2],[0,2,3]],"thickness":0.05,"material":"concrete",
 "materials":{"concrete":{"E":3e10,"nu":0.2,"density":2400},"steel":{"E":2.1e11}},
 "supports":[{"node":0,"fix":"clamped"},{"node":1,"fix":["ux","uy","uz"]},{"node":3}],
 "loads":[{"node":2,"force":[0,0,-1e3]},{"type":"pressure","p":500},{"type":"self_weight"},
          {"type":"surface","q":[0,0,-1]},{"type":"projected","q":[0,0,-1]}]}
w("model/shell.json",json.dumps(shell,indent=1))
both=dict(frame); both.update({"triangles":[[0,1,2],[0,2,3]],"thickness":0.1}); del both["faces"]
w("model/frame_and_shell.json",json.dumps(both))
w("model/shell_polygon_faces.json",json.dumps({"nodes":nodes,"faces":[[0,1,2,3]],"supports":[{"node":0,"fix":"pinned"}]}))
w("model/broken_member_node.json",json.dumps({"nodes":nodes,"sections":{"s":{"shape":"circle","diameter":0.1}},"materials":{"m":{"E":1e9}},"members":[{"nodes":[0,7]}]}))
w("model/broken_triangle.json",json.dumps({"nodes":nodes,"triangles":[[0,1,1]]}))
w("model/broken_types.json",'{"nodes":[[0,0,"x"]],"sections":[],"members":{}}')
w("model/broken_syntax.json",'{"nodes": [[0, 0, 0], [1, 0, 0]], "members": [{"nodes": [0, 1]')
