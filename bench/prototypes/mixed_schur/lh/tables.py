import json
f = lambda v: '-' if v is None else str(v)
for fn in ['lh_q8n2.json', 'lh_q4n2_q4n4.json']:
    d = json.load(open(fn))
    cfgs = sorted(set((r['kind'], r['ny']) for r in d), reverse=True)
    for kind, ny in cfgs:
        rs = [r for r in d if r['kind'] == kind and r['ny'] == ny]
        print(f"\n#### Quad{kind}, {ny} elements through the depth (ndof: " + ', '.join(f"{r['lh']}: {r['ndof']}" for r in rs) + ")")
        print("| preconditioner | measure | " + ' | '.join(f"L/h={r['lh']}" for r in rs) + " |")
        print("|---|---|" + '---|' * len(rs))
        for name in rs[0]['runs']:
            print(f"| {name} | true l2 res 5e-3 / 1e-4 / 1e-8 | " + ' | '.join(
                '/'.join(f(v) for v in r['runs'][name]['its']) for r in rs) + ' |')
            print(f"|  | floor (min true l2 res) | " + ' | '.join(f"{r['runs'][name]['floor']:.1e}" for r in rs) + ' |')
            print(f"|  | Kd-norm error 5e-3 / 1e-4 / 1e-8 | " + ' | '.join(
                '/'.join(f(v) for v in r['runs'][name]['eits']) for r in rs) + ' |')
            if 'zits' in rs[0]['runs'][name]:
                print(f"|  | B-norm res sqrt(r'Br/b'Bb) 5e-3 / 1e-4 / 1e-8 | " + ' | '.join(
                    '/'.join(f(v) for v in r['runs'][name]['zits']) for r in rs) + ' |')
        print(f"| direct solve (saddle LU + 4 refinements) | l2 res of S_a | " + ' | '.join(f"{r['direct_floor_S']:.1e}" for r in rs) + ' |')
        print(f"| direct Kd solve (splu) | l2 res of Kd | " + ' | '.join(f"{r['direct_floor_Kd']:.1e}" for r in rs) + ' |')
        print(f"| first-iteration l2 res, E1 | | " + ' | '.join(f"{r['runs']['E1 Kd^-1']['hist'][0]:.1e}" for r in rs) + ' |')
